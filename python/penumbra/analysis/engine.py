"""What the analyses need of the engine and the lab, read from them rather than copied: the
calibration's factors (``src/methods/calibration.rs``), the promise ``auto`` is judged by
(``lab/src/studies/frontier/budget.rs``), a method spec's parameters as the engine parses them,
and the two laws the results' analyses replay (``auto``'s ``predicted_at``, ``regions``'
``half_octave``). A change to any of them reaches every analysis with the next build of the
package, and a figure computed before it fails its test instead of going stale unseen.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .. import _penumbra

LIGHT_CLASSES = ("plane", "cube")


@dataclass(frozen=True)
class Factors:
    """The calibration's two safety factors (``calibration::Factors``).

    Attributes:
        sampling: The sampling part's factor.
        map: The maps' part's factor.
    """

    sampling: float
    map: float


@dataclass(frozen=True)
class Calibration:
    """The calibrated estimate's factors, as the engine ships them.

    Attributes:
        plane: Rectangle, disk, sun and spot lights (one map per sample).
        cube: Point and ball lights (six cube faces per sample).
        even_sampling: The even sides' own sampling factor per light class.
        max_fitted_even: The largest even side the even factors were fitted on.
        min_fitted_size: The smallest map side the factors were fitted on.
        coverage_percent: The share of pairs a fit covers (predicted at least measured), in percent.
        split: The shipped scenes' halves (``fitting``, ``checking``), by scene.
    """

    plane: Factors
    cube: Factors
    even_sampling: Mapping[str, float]
    max_fitted_even: int
    min_fitted_size: int
    coverage_percent: int
    split: Mapping[str, str]

    def half(self, scene: str) -> str:
        """A scene's half of the split (``calibration::half``): a scene not shipped is held out.

        Args:
            scene: The scene's name.

        Returns:
            ``fitting``, ``checking`` or ``held out``.
        """
        return self.split.get(scene, "held out")

    def factors(self, light_class: str, n: int = 1) -> Factors:
        """The factors of a grid of side ``n`` (``calibration::factors_at``): the class's on an
        odd side, the even sides' sampling factor with the class's maps' factor on an even one.

        Args:
            light_class: ``plane`` or ``cube``.
            n: The grid's side (odd by default).

        Returns:
            The factors.

        Raises:
            ValueError: An unknown light class.
        """
        if light_class not in LIGHT_CLASSES:
            raise ValueError(f"light class {light_class!r}: expected one of {', '.join(LIGHT_CLASSES)}")
        f = self.plane if light_class == "plane" else self.cube
        if n % 2 == 1:
            return f
        return Factors(self.even_sampling[light_class], f.map)


@dataclass(frozen=True)
class Promise:
    """``auto``'s promise (docs/budget.md): measured RMSE at most T on ``met_share`` of rows, and
    time at most ``time_ratio`` × the oracle's on ``time_share`` of them.

    Attributes:
        met_share: The share of rows that must measure at most T.
        time_ratio: The most time over the oracle's a row may take.
        time_share: The share of rows (with an oracle) that must keep within it.
    """

    met_share: float
    time_ratio: float
    time_share: float


@functools.lru_cache(maxsize=None)
def _constants() -> Mapping[str, Any]:
    c: Mapping[str, Any] = _penumbra.analysis_constants()
    return c


def calibration() -> Calibration:
    """The engine's calibration factors.

    Returns:
        The factors the engine's ``auto`` chooses by.
    """
    c = _constants()["calibration"]
    return Calibration(
        plane=Factors(**c["plane"]),
        cube=Factors(**c["cube"]),
        even_sampling=dict(c["even_sampling"]),
        max_fitted_even=int(c["max_fitted_even"]),
        min_fitted_size=int(c["min_fitted_size"]),
        coverage_percent=int(c["coverage_percent"]),
        split=dict(c["split"]),
    )


def promise() -> Promise:
    """The promise the lab counts ``auto``'s rows against.

    Returns:
        The shares and the time ratio.
    """
    return Promise(**_constants()["promise"])


def sampling_order() -> float:
    """The order ``auto`` extrapolates a grid's sampling error by: it falls as n^-order.

    Returns:
        The order (1.5).
    """
    return float(_constants()["auto"]["sampling_order"])


def window() -> float:
    """How far over its measure a prediction may read before ``auto`` buys more than the time
    ratio's maps: maps grow as n², the sampling error falls as n^-order, so as
    maps^-(order/2), and a prediction ``time_ratio^(order/2)`` over its measure buys
    ``time_ratio`` × the maps a truthful one would.

    Returns:
        The window W (1.3^0.75 = 1.217).
    """
    return float(promise().time_ratio ** (sampling_order() / 2))


def method_params(spec: str) -> dict[str, Any]:
    """A method spec's parameters as the engine parses it, defaults included (run.json's
    ``params``): ``method_params("auto:target=0.03")["target"]`` is 0.03.

    Args:
        spec: A method spec, as ``--method`` takes it.

    Returns:
        The parameters, and the method's name under ``method``.

    Raises:
        penumbra.PenumbraError: A spec the engine refuses.
    """
    return dict(_penumbra.method_params(spec))


def predicted_at(light_class: str, n: int, size: int, prediction: Mapping[str, float], n2: int, size2: int) -> float:
    """``auto``'s prediction of the centred grid (n2, size2) from a try at (n, size)
    (``auto::predicted_at``).

    Args:
        light_class: ``plane`` or ``cube``.
        n: The try's side.
        size: The try's map side.
        prediction: The try's calibrated parts: ``predicted_sampling``, ``predicted_map``,
            ``predicted_map_averaging`` (a try of run.json's ``method_record.tries``).
        n2: The grid's side.
        size2: The grid's map side.

    Returns:
        The predicted RMSE.
    """
    return float(_penumbra.auto_predicted_at(light_class, n, size, dict(prediction), n2, size2))


def half_octave(want: float) -> int:
    """``regions``' map side for a wanted side (``regions::half_octave``): the next half-octave
    step, a multiple of 16.

    Args:
        want: The wanted side in texels.

    Returns:
        The side.
    """
    return int(_penumbra.regions_half_octave(want))


def light_class_of_try(maps: int, n: int) -> str:
    """The light class a try of ``auto`` ran in, from its own maps: a plane light renders one map
    per sample, a cube-mapped light six.

    Args:
        maps: The try's maps.
        n: Its side.

    Returns:
        ``plane`` or ``cube``.

    Raises:
        ValueError: Maps that are neither n² nor 6n².
    """
    if maps == n * n:
        return "plane"
    if maps == 6 * n * n:
        return "cube"
    raise ValueError(f"{maps} maps for a side of {n}: neither n² nor 6n²")


def density_floor(bias: Mapping[str, float]) -> float:
    """``regions``' least texels per pixel footprint under a scene's bias, with its ``density``
    parameter unset (``regions::density_floor``).

    Args:
        bias: run.json's ``render.bias`` (``constant``, ``slope``, ``normal_offset``, in texels).

    Returns:
        The floor.
    """
    return float(_penumbra.regions_density_floor(float(bias["constant"]), float(bias["slope"]), float(bias["normal_offset"])))
