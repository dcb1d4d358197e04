"""Penumbra from Python: soft shadows from area lights, rendered on the GPU (wgpu), with the
CPU ground truth, compare's metrics and studies as numpy arrays and dicts.

    import penumbra
    scene = penumbra.Scene.load("analytic-square", resolution=128)
    v, record = penumbra.Renderer(scene).render("adaptive:preset=balanced")
    ref = penumbra.reference(scene, samples=32)
    print(penumbra.metrics(v, ref)["rmse"])
    frame = penumbra.compare(scene, ["hard", "pcss"]).to_frame()   # with pandas

Bad input raises `PenumbraError` (a `ValueError`), a failing GPU `GpuError` (a `RuntimeError`).
docs/python.md is the guide; the signatures are typed (`_penumbra.pyi`, `py.typed`).
"""

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Optional, Union

from . import _penumbra
from ._penumbra import (
    GpuError,
    PenumbraError,
    Record,
    Reference,
    Renderer,
    Scene,
    __version__,
    metrics,
    read_exr,
    reference,
)

if TYPE_CHECKING:  # pragma: no cover - only for the type checker
    import pandas

__all__ = [
    "GpuError",
    "PenumbraError",
    "Record",
    "Reference",
    "Renderer",
    "Rows",
    "Scene",
    "__version__",
    "compare",
    "metrics",
    "read_exr",
    "reference",
    "rows_to_frame",
]

# A run record reads as a dict does (built on first read); it is a Mapping for isinstance checks.
Mapping.register(Record)


class Rows(List[Dict[str, Any]]):
    """compare's rows, results.jsonl's as dicts, in a list; `to_frame()` makes them a pandas DataFrame."""

    def to_frame(self) -> "pandas.DataFrame":
        """The rows as a pandas DataFrame, one row per method (see `rows_to_frame`).

        Raises:
            ImportError: pandas is not installed.
        """
        return rows_to_frame(self)


def compare(
    scene: Scene,
    methods: Union[str, Sequence[str]],
    repeats: int = 3,
    samples: int = 32,
    reference: str = "continuous",
    no_cache: bool = False,
    adapter: Optional[str] = None,
    progress: Union[None, bool, Callable[[str], object]] = None,
) -> Rows:
    """`penumbra compare` on `scene`: each method timed after a warm-up frame and judged against the reference.

    Args:
        scene: the scene.
        methods: method specs, or one comma-separated string (`"hard,pcss,regular:n=5"`).
        repeats: timed frames per method (1..=1000); the row's `frame_ms` is their median.
        samples: the continuous reference's samples per side.
        reference: `continuous`, `lattice` or `point[:S,T]`, as for `reference`.
        no_cache: trace the reference afresh.
        adapter: the GPU adapter, as for `Renderer`.
        progress: `None`: the reference's line and each method's figures on a terminal's stderr,
            or in a Jupyter cell; `True`: on Python's `sys.stderr`; `False`: nothing; a callable:
            called with each line.

    Returns:
        The rows of results.jsonl (without `images`: nothing is written but the reference cache),
        one dict per method: `label`, `maps`, `frame_ms`, `metrics` (`rmse`, `flip_mean`,
        ...), `adapter`, ... `.to_frame()` gives a pandas DataFrame.

    Raises:
        PenumbraError: an unknown method or parameter, a method twice, `repeats` out of range, a
            bad reference mode.
        GpuError: the device failed.
    """
    return Rows(_penumbra.compare(scene, methods, repeats, samples, reference, no_cache, adapter, progress))


def rows_to_frame(rows: Sequence[Mapping[str, Any]]) -> "pandas.DataFrame":
    """compare's rows as a pandas DataFrame, the nested ``metrics`` flattened to ``metrics.rmse``, ….

    Args:
        rows: rows as `compare` returns them (or read from a results.jsonl).

    Returns:
        One DataFrame row per result row; the columns are the rows' keys.

    Raises:
        ImportError: pandas is not installed (it is not a dependency of this package).
    """
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("penumbra.rows_to_frame needs pandas: pip install pandas") from e
    return pandas.json_normalize(list(rows))
