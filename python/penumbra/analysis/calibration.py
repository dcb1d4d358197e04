"""The calibrated estimate's (scene, setting) pairs (docs/budget.md §2–4): each pair's predicted
parts against its measured error, read with the engine's factors
(:func:`penumbra.analysis.engine.calibration`), and the analyses results/budget-calibration/
prints: the coverage window (:func:`spread`), factors per class of scene (:func:`classes`), which
part stops coverage (:func:`misses`), the maps' error's order in the map size
(:func:`map_order`), and the even sides' own sampling factor (:func:`even_sides`).

A pair comes from ``pairs.csv`` (``penumbra calibrate``) or from an estimate's rows
(``penumbra estimate``, ``estimates/*.jsonl``); its grid's side and layout are the engine's parse
of its spec, its half the lab's split, its light class its own maps (six per sample for a cube).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Optional

from . import engine
from .rows import PathLike, Row, Table, read
from .stats import least_covering, median, quantile, spearman

HALVES = ("fitting", "checking", "held out")


@dataclass(frozen=True)
class Pair:
    """One (scene, setting) pair.

    Attributes:
        scene: The scene.
        half: ``fitting``, ``checking`` or ``held out``.
        light_class: ``plane`` or ``cube``.
        spec: The grid's spec.
        n: Its side.
        layout: ``centred``, ``lattice`` or ``jittered``.
        map_size: Its map side.
        maps: Its maps.
        measured_rmse: Measured RMSE of V.
        predicted_sampling: The estimate's sampling part (raw).
        predicted_map: Its maps' part (raw).
        measured_sampling: The sampling part's own measure.
        measured_map: The maps' part's own measure.
        calibrated: ``penumbra calibrate``'s calibrated prediction (pairs.csv), or None.
        extra: The estimate's other figures (``predicted_quantization``, …), where read from it.
    """

    scene: str
    half: str
    light_class: str
    spec: str
    n: int
    layout: str
    map_size: int
    maps: int
    measured_rmse: float
    predicted_sampling: float
    predicted_map: float
    measured_sampling: float
    measured_map: float
    calibrated: Optional[float] = None
    extra: Mapping[str, float] = field(default_factory=dict)

    def with_factors(self, f: engine.Factors, ka: float = 1.0, kb: float = 1.0) -> float:
        """The prediction with each part times its factor (and a stretch of each).

        Args:
            f: The factors.
            ka: A stretch of the sampling part's factor.
            kb: A stretch of the maps' part's factor.

        Returns:
            The calibrated predicted RMSE.
        """
        return math.hypot(ka * f.sampling * self.predicted_sampling, kb * f.map * self.predicted_map)

    @property
    def need(self) -> float:
        """The factor the maps' part needs to reach its own measure."""
        return self.measured_map / self.predicted_map


def _grid(row: Row) -> tuple[int, str]:
    return row.integer("params.n"), row.text("params.layout")


def pair_of(row: Row, half: Optional[str] = None, light_class: Optional[str] = None) -> Pair:
    """A pair from a row of pairs.csv or of an estimate.

    Args:
        row: The row.
        half: The half, where the row has no ``half`` column (the lab's split by default).
        light_class: The light class, where the row has no ``class`` column (from its maps by default).

    Returns:
        The pair.
    """
    spec = row.text("spec")
    n, layout = _grid(row)
    maps = row.integer("maps")
    extra = {k: row.number(k) for k in ("predicted_quantization", "predicted_map_averaging", "bound_coverage") if row.has(k)}
    return Pair(
        scene=row.text("scene"),
        half=row.text("half") if row.has("half") else (half or engine.calibration().half(row.text("scene"))),
        light_class=row.text("class") if row.has("class") else (light_class or engine.light_class_of_try(maps, n)),
        spec=spec, n=n, layout=layout, map_size=row.integer("map_size"), maps=maps,
        measured_rmse=row.number("rmse"), predicted_sampling=row.number("predicted_sampling"),
        predicted_map=row.number("predicted_map"), measured_sampling=row.number("measured_sampling"),
        measured_map=row.number("measured_map"), calibrated=row.optional_number("calibrated"), extra=extra,
    )


def read_pairs(path: PathLike) -> list[Pair]:
    """The pairs of ``pairs.csv``."""
    return [pair_of(r) for r in read(path)]


def read_estimates(paths: Iterable[PathLike]) -> list[Pair]:
    """The pairs of estimate rows (``estimates/*.jsonl``), file after file."""
    return [pair_of(r) for p in paths for r in read(p)]


def _pct(k: int, n: int) -> str:
    return f"{100 * k / n:.1f}%"


# --- spread.py ------------------------------------------------------------------------------

SPREAD_SHOWN = (105, 110, 115, 120, 130, 140)


def spread(pairs: Sequence[Pair]) -> str:
    """Why one calibration cannot keep both of ``auto``'s promises: for the fitted factors times a
    stretch s from 0.5 to 3, the share of pairs covered (calibrated/measured at least 1) and the
    share inside [1, W] (:func:`penumbra.analysis.engine.window`), per half; then the spread of
    measured/calibrated (q95/q10), which a window of width W must hold.

    Args:
        pairs: The pairs of pairs.csv (their ``calibrated`` column).

    Returns:
        The report, as README.md quotes it.
    """
    w = engine.window()
    halves = {"fitting": [p for p in pairs if p.half == "fitting"], "checking and held out": [p for p in pairs if p.half != "fitting"]}
    ratio = {h: [_calibrated(p) / p.measured_rmse for p in ps] for h, ps in halves.items()}
    lines = [f"window W = {engine.promise().time_ratio:g}^{engine.sampling_order() / 2:g} = {w:.3f}",
             "| stretch | " + " | ".join(f"{h}: covered | {h}: in [1, W]" for h in halves) + " |",
             "|---:|" + "---:|---:|" * len(halves)]
    best = {h: (0.0, 0.0) for h in halves}
    for i in range(50, 301, 5):
        s = i / 100
        cells = []
        for h, xs in ratio.items():
            covered = sum(1 for x in xs if s * x >= 1) / len(xs)
            inside = sum(1 for x in xs if 1 <= s * x <= w) / len(xs)
            best[h] = max(best[h], (inside, s))
            cells += [f"{100 * covered:.1f}%", f"{100 * inside:.1f}%"]
        if i % 25 == 0 or i in SPREAD_SHOWN:
            lines.append(f"| {s:.2f} | " + " | ".join(cells) + " |")
    lines.append("")
    for h, xs in ratio.items():
        m = [1 / x for x in xs]
        lines.append(f"{h}: {len(xs)} pairs; measured/calibrated q10 {quantile(m, 0.10):.2f}, median {quantile(m, 0.5):.2f}, q95 {quantile(m, 0.95):.2f}, "
                     f"q95/q10 {quantile(m, 0.95) / quantile(m, 0.10):.2f} (a window of W = {w:.2f} holds both promises); "
                     f"the most pairs inside [1, W] at any stretch: {100 * best[h][0]:.1f}% (s = {best[h][1]:.2f})")
    return "\n".join(lines)


def _calibrated(p: Pair) -> float:
    if p.calibrated is None:
        raise ValueError(f"{p.scene} {p.spec} @ {p.map_size}: no calibrated column (pairs.csv's)")
    return p.calibrated


# --- classes.py -----------------------------------------------------------------------------

FACTOR_GRID = [k / 100 for k in range(50, 1001)]


def least_factor(pairs: Sequence[Pair], covered: Callable[[Pair, float], bool]) -> float:
    """The engine's fitting rule: the least factor on a 0.01 grid from 0.5 that covers the
    calibration's share of the pairs (``coverage_percent``, 95).

    Args:
        pairs: The pairs to cover.
        covered: Whether a pair is covered at a factor.

    Returns:
        The factor.

    Raises:
        ValueError: No factor up to 10 covers 95%.
    """
    percent = engine.calibration().coverage_percent
    k = least_covering(FACTOR_GRID, pairs, covered, percent)
    if k is None:
        raise ValueError(f"no factor up to 10 covers {percent}% of {len(pairs)} pairs")
    return k


def _reading(ps: Sequence[Pair], f: Callable[[Pair], engine.Factors]) -> str:
    r = [p.with_factors(f(p)) / p.measured_rmse for p in ps]
    return f"{sum(x >= 1 for x in r)} of {len(r)}, median {median(r):.2f}" if r else "-"


@dataclass(frozen=True)
class ClassFit:
    """A class of scenes given its own maps' factor, fitted on its fitting-half pairs.

    Attributes:
        name: The class.
        fitted_on: Its fitting-half scenes.
        map: Its maps' factor.
        sampling: Its own sampling factor (a light class refits it), or None (its light's).
        cells: Readings of its pairs and of all pairs, checking and held out.
    """

    name: str
    fitted_on: Sequence[str]
    map: float
    sampling: Optional[float]
    cells: Sequence[str]


def classes(pairs: Sequence[Pair], estimates: Sequence[Pair], groups: Mapping[str, Callable[[Pair], bool]], light_groups: Sequence[str],
            before: Mapping[str, engine.Factors]) -> tuple[str, list[ClassFit]]:
    """Which data measure separates the pairs whose maps' part under-reads: each scene's needed
    maps' factor; candidate classes, each with its own maps' factor fitted on the fitting half
    alone (the least that covers 95% of the class's maps' part on its own measure) and, for a
    light class, its own sampling factor; then the frame's own measures against the needed factor
    (Spearman's rho).

    Args:
        pairs: The pairs of pairs.csv (their half and class).
        estimates: The same pairs from the estimates (their terms), matched by scene, spec and size.
        groups: The candidate classes: a name and which pairs belong.
        light_groups: The names of ``groups`` that are classes of light (they refit the sampling factor).
        before: The factors every class had before, per light class.

    Returns:
        The report as README.md quotes it, and each class's fit.
    """
    est = {(e.scene, e.spec, e.map_size): e for e in estimates}
    ps = [replace(est[(p.scene, p.spec, p.map_size)], half=p.half, light_class=p.light_class) for p in pairs]
    lines = ["| scene | half | light | maps' part needs (6 settings) | median |", "|---|---|---|---:|---:|"]
    scenes = sorted({p.scene for p in ps}, key=lambda s: (HALVES.index(next(p.half for p in ps if p.scene == s)), s))
    for s in scenes:
        mine = [p for p in ps if p.scene == s]
        v = [p.need for p in mine]
        lines.append(f"| {s} | {mine[0].half} | {mine[0].light_class} | {min(v):.2f}–{max(v):.2f} | {median(v):.2f} |")

    def old(p: Pair) -> engine.Factors:
        return before[p.light_class]

    lines += ["", "| class with its own factors | fitted on | maps' factor | sampling factor | class: checking | class: held out | all: checking | all: held out |",
              "|---|---|---:|---:|---|---|---|---|",
              f"| none (one maps' factor) | | | | | | {_reading([p for p in ps if p.half == 'checking'], old)} | {_reading([p for p in ps if p.half == 'held out'], old)} |"]
    fits = []
    for name, inc in groups.items():
        fit = [p for p in ps if p.half == "fitting" and inc(p)]
        b = least_factor(fit, lambda p, k: k * p.predicted_map >= p.measured_map)

        def covers(p: Pair, k: float, b: float = b) -> bool:
            return p.with_factors(engine.Factors(k, b)) >= p.measured_rmse

        a = least_factor(fit, covers) if name in light_groups else None

        def f(p: Pair, a: Optional[float] = a, b: float = b, inc: Callable[[Pair], bool] = inc) -> engine.Factors:
            return engine.Factors(a or before[p.light_class].sampling, b) if inc(p) else before[p.light_class]

        cells = [_reading([p for p in ps if p.half == h and (inc(p) if k < 2 else True)], f) for k, h in enumerate(("checking", "held out", "checking", "held out"))]
        fitted_on = sorted({p.scene for p in fit})
        fits.append(ClassFit(name, fitted_on, b, a, cells))
        lines.append(f"| {name} | {', '.join(fitted_on)} | {b:.2f} | {'%.2f' % a if a else 'as its light'} | " + " | ".join(cells) + " |")

    measures: dict[str, Callable[[Pair], float]] = {
        "quantization share of the maps' part": lambda p: p.extra["predicted_quantization"] / p.predicted_map,
        "averaging share of the maps' part": lambda p: p.extra["predicted_map_averaging"] / p.predicted_map,
        "maps' part over sampling part": lambda p: p.predicted_map / p.predicted_sampling,
        "maps' part": lambda p: p.predicted_map,
        "map size": lambda p: p.map_size,
        "maps": lambda p: p.maps,
        "bound coverage": lambda p: p.extra["bound_coverage"],
    }
    lines += ["", "| frame measure (plane lights) | rho, fitting | rho, checking and held out |", "|---|---:|---:|"]
    for name, m in measures.items():
        cells = []
        for hs in (("fitting",), ("checking", "held out")):
            sel = [p for p in ps if p.half in hs and p.light_class == "plane"]
            cells.append(f"{spearman([m(p) for p in sel], [p.need for p in sel]):+.2f}")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines), fits


# --- misses.py ------------------------------------------------------------------------------

MISSES_HEADER = ["scene", "half", "light_class", "scene_class", "setting", "map_size", "calibrated_over_measured", "sampling_part_over_measure",
                 "maps_part_over_measure", "stops"]


def grid_kind(p: Pair) -> str:
    """``odd centred (auto)`` for the grids ``auto`` chooses, else ``LAYOUT N``."""
    return "odd centred (auto)" if p.layout == "centred" and p.n % 2 else f"{p.layout} {p.n}"


def _share() -> float:
    # The calibration's coverage as a share (95 / 100 is the double 0.95).
    return engine.calibration().coverage_percent / 100


def _parts(p: Pair) -> tuple[float, float]:
    f = engine.calibration().factors(p.light_class)
    return f.sampling * p.predicted_sampling, f.map * p.predicted_map


def _cal(p: Pair, ka: float = 1.0, kb: float = 1.0) -> float:
    s, m = _parts(p)
    return math.hypot(ka * s, kb * m)


def stops(p: Pair) -> str:
    """The part that stops a pair: the one that, raised to its own measure, covers it alone
    (the one further under its measure where either would; ``both`` where neither does)."""
    s, m = _parts(p)
    fs = math.hypot(max(s, p.measured_sampling), m) >= p.measured_rmse
    fm = math.hypot(s, max(m, p.measured_map)) >= p.measured_rmse
    if fs and fm:
        return "sampling" if s / p.measured_sampling < m / p.measured_map else "maps"
    return "sampling" if fs else ("maps" if fm else "both")


def misses(pairs: Sequence[Pair], scene_class: Mapping[str, str], default_class: str) -> tuple[str, list[list[object]]]:
    """Which part stops coverage on the checking and held-out pairs (engine factors, the class's
    odd-side factors as the pairs are odd or fixed grids): by light class, scene class, grid and
    map size; the stretch each part alone (and both) would need for 95%; the best per-part pair;
    and a margin sized by leaving each fitting plane-light scene out.

    Args:
        pairs: The pairs of pairs.csv.
        scene_class: Each scene's class (what its occluders are), to read the misses by.
        default_class: The class of a scene not in ``scene_class``.

    Returns:
        The report as README.md quotes it, and misses.csv's rows (:data:`MISSES_HEADER`).
    """
    read_ = [p for p in pairs if p.half != "fitting"]
    miss = [p for p in read_ if _cal(p) < p.measured_rmse]
    rows: list[list[object]] = []
    for p in miss:
        s, m = _parts(p)
        rows.append([p.scene, p.half, p.light_class, scene_class.get(p.scene, default_class), p.spec, p.map_size, f"{_cal(p) / p.measured_rmse:.3f}",
                     f"{s / p.measured_sampling:.3f}", f"{m / p.measured_map:.3f}", stops(p)])
    keys: dict[str, Callable[[Pair], object]] = {
        "class": lambda p: p.light_class,
        "scene_class": lambda p: scene_class.get(p.scene, default_class),
        "kind": grid_kind,
        "map_size": lambda p: str(p.map_size),
    }
    lines = [f"checking and held out: {len(read_)} pairs, {len(miss)} under ({100 * (1 - len(miss) / len(read_)):.1f}% covered)"]
    for key, of in keys.items():
        lines += ["", f"| {key} | pairs | under | sampling stops | maps stop | both |", "|---|---:|---:|---:|---:|---:|"]
        for v in sorted({str(of(p)) for p in read_}):
            ps = [p for p in read_ if str(of(p)) == v]
            ms = [p for p in miss if str(of(p)) == v]
            c = [sum(stops(p) == part for p in ms) for part in ("sampling", "maps", "both")]
            lines.append(f"| {v} | {len(ps)} | {len(ms)} | {c[0]} | {c[1]} | {c[2]} |")

    def need(ps: Sequence[Pair], part: str) -> tuple[Optional[float], Optional[float]]:
        for k in [1 + x / 100 for x in range(0, 401)]:
            ka, kb = (k, 1.0) if part == "sampling" else (1.0, k) if part == "maps" else (k, k)
            if sum(_cal(p, ka, kb) >= p.measured_rmse for p in ps) >= _share() * len(ps):
                return k, median(_cal(p, ka, kb) / p.measured_rmse for p in ps)
        return None, None

    lines += ["", "| pairs | sampling part alone | maps' part alone | both parts |", "|---|---:|---:|---:|"]
    for name, ps in (("checking and held out", read_), ("odd centred grids only (auto's)", [p for p in read_ if grid_kind(p).startswith("odd")])):
        cells = []
        for part in ("sampling", "maps", "both"):
            stretch, med = need(ps, part)
            cells.append("never (to 5.00)" if stretch is None or med is None else f"× {stretch:.2f} (median {med:.2f})")
        lines.append(f"| {name} ({len(ps)}) | " + " | ".join(cells) + " |")

    # The least median over-prediction any per-part stretch reaches at 95% of these pairs, read
    # where it is fitted: a bound on what any such stretch costs, not a calibration.
    grid = [1 + x / 50 for x in range(0, 101)]
    best: Optional[tuple[float, float, float]] = None
    for ka in grid:
        for kb in grid:
            if sum(_cal(p, ka, kb) >= p.measured_rmse for p in read_) >= _share() * len(read_):
                m = median(_cal(p, ka, kb) / p.measured_rmse for p in read_)
                if best is None or m < best[0]:
                    best = (m, ka, kb)
    assert best is not None
    lines += ["", f"per-part stretch, the least median at 95% of the checking and held-out pairs: sampling × {best[1]:.2f}, maps × {best[2]:.2f}, median {best[0]:.2f}"]

    # A margin sized on the fitting half alone: leave one plane-light scene out, refit (a, b) on
    # the others by the engine's rule (95% of pairs, least median; a 0.02 grid), read the scene
    # left out; the stretch that covers 95% of those out-of-fit pairs is the margin.
    fitting = [p for p in pairs if p.half == "fitting" and p.light_class == "plane"]
    out_of_fit: list[float] = []
    for scene in sorted({p.scene for p in fitting}):
        a, b = refit([p for p in fitting if p.scene != scene])
        out_of_fit += [math.hypot(a * p.predicted_sampling, b * p.predicted_map) / p.measured_rmse for p in fitting if p.scene == scene]
    k = next(k for k in [1 + x / 100 for x in range(0, 301)] if sum(k * r >= 1 for r in out_of_fit) >= _share() * len(out_of_fit))
    lines += ["", f"leave-one-scene-out on the fitting half: {sum(r >= 1 for r in out_of_fit)} of {len(out_of_fit)} covered; 95% from a stretch of {k:.2f}"]
    for name, ps in (("checking", [p for p in read_ if p.half == "checking"]), ("held out", [p for p in read_ if p.half == "held out"]), ("both", read_)):
        cov = sum(_cal(p, k, k) >= p.measured_rmse for p in ps)
        lines.append(f"  × {k:.2f} on {name}: {cov} of {len(ps)} ({100 * cov / len(ps):.1f}%), median {median(_cal(p, k, k) / p.measured_rmse for p in ps):.2f}")
    return "\n".join(lines), rows


def refit(pairs: Sequence[Pair]) -> tuple[float, float]:
    """Both factors refitted by the engine's rule on a 0.02 grid from 0.6 to 3: of the (a, b)
    that cover 95% of the pairs, the one with the least median over-prediction.

    Args:
        pairs: The pairs.

    Returns:
        (sampling factor, maps' factor).
    """
    g = [x / 100 for x in range(60, 301, 2)]
    out: Optional[tuple[float, float, float]] = None
    for a in g:
        for b in g:
            if sum(math.hypot(a * p.predicted_sampling, b * p.predicted_map) >= p.measured_rmse for p in pairs) >= _share() * len(pairs):
                m = median(math.hypot(a * p.predicted_sampling, b * p.predicted_map) / p.measured_rmse for p in pairs)
                if out is None or m < out[0]:
                    out = (m, a, b)
    if out is None:
        raise ValueError(f"no factors up to 3 cover 95% of {len(pairs)} pairs")
    return out[1], out[2]


# --- map_order.py ---------------------------------------------------------------------------

def map_order(pairs: Sequence[Pair]) -> tuple[list[list[object]], list[str]]:
    """How fast the maps' error falls with the map size: for each setting measured at both 512²
    and 1024², the order a in measured_map(1024) = measured_map(512) · 2^-a (1: as the texel
    size, the law ``auto`` extrapolates by), and the same for the estimate's maps' part.

    Args:
        pairs: The pairs.

    Returns:
        map-order.csv's rows (half, scene, spec, the two orders to 3 decimals) and the medians per half.
    """
    at: dict[tuple[str, str, str], dict[int, Pair]] = {}
    for p in pairs:
        at.setdefault((p.half, p.scene, p.spec), {})[p.map_size] = p
    out: list[tuple[str, str, str, float, float]] = []
    for (half, scene, spec), d in sorted(at.items()):
        if 512 not in d or 1024 not in d:
            continue
        a, b = d[512], d[1024]

        def order(x: float, y: float) -> float:
            return math.log2(x / y) if min(x, y) > 0 else float("nan")

        out.append((half, scene, spec, order(a.measured_map, b.measured_map), order(a.predicted_map, b.predicted_map)))
    rows: list[list[object]] = [[h, s, spec, f"{m:.3f}", f"{e:.3f}"] for h, s, spec, m, e in out]
    medians = []
    for half in HALVES:
        ms = [m for h, *_, m, _ in out if h == half]
        es = [e for h, *_, _, e in out if h == half]
        if ms:
            medians.append(f"{half}: {len(ms)} settings, median measured order {median(ms):.2f}, estimate's {median(es):.2f}")
    return rows, medians


# --- even/even.py ---------------------------------------------------------------------------

EVEN_HEADER = ["scene", "half", "class", "spec", "map_size", "maps", "measured_rmse", "predicted_sampling", "predicted_map", "measured_sampling",
               "measured_map", "engine_over_measured", "even_factor_over_measured"]


def even_sides(even: Sequence[Pair], pairs: Sequence[Pair]) -> tuple[str, list[list[object]], dict[str, float]]:
    """Even sides: per light class, the least sampling factor (0.01 steps from 0.5) that covers
    95% of the fitting half's even pairs with the class's maps' factor, read on the checking half,
    against the class's factors on the odd centred pairs.

    Args:
        even: The even pairs (``even/estimates/``).
        pairs: The pairs of pairs.csv (their odd centred ones are read).

    Returns:
        The report as README.md quotes it, even.csv's rows (:data:`EVEN_HEADER`), and the fitted
        factor per light class (which the engine ships as the even sides' sampling factor).
    """
    cal = engine.calibration()
    odd = [p for p in pairs if p.layout == "centred" and p.n % 2 and p.half != "held out"]

    def ratio(p: Pair, a: float) -> float:
        return p.with_factors(engine.Factors(a, cal.factors(p.light_class).map)) / p.measured_rmse

    def reading(ps: Sequence[Pair], fa: Callable[[Pair], float]) -> tuple[int, int, float]:
        r = [ratio(p, fa(p)) for p in ps]
        return len(r), sum(x >= 1 for x in r), median(r) if r else float("nan")

    fit = {c: least_factor([p for p in even if p.half == "fitting" and p.light_class == c], lambda p, a: ratio(p, a) >= 1) for c in ("plane", "cube")}

    def odd_factor(p: Pair) -> float:
        return cal.factors(p.light_class).sampling

    def own(p: Pair) -> float:
        return fit[p.light_class]

    lines = ["even sides' sampling factor, fitted on the fitting half's even pairs: plane %.2f, ball %.2f" % (fit["plane"], fit["cube"]), "",
             "| pairs | n | predicted ≥ measured | median predicted/measured |", "|---|---:|---:|---:|"]
    for half in ("fitting", "checking"):
        for name, ps, fa in (("%s half, odd centred (n = 3, 5, 9), engine factors" % half, [p for p in odd if p.half == half], odd_factor),
                             ("%s half, even (n = 2, 4, 6), engine factors" % half, [p for p in even if p.half == half], odd_factor),
                             ("%s half, even, own sampling factor" % half, [p for p in even if p.half == half], own)):
            n, k, m = reading(ps, fa)
            lines.append("| %s | %d | %d (%.1f%%) | %.2f |" % (name, n, k, 100 * k / n, m))
    rows: list[list[object]] = []
    for p in even:
        rows.append([p.scene, p.half, p.light_class, p.spec, p.map_size, p.maps, "%.6f" % p.measured_rmse, "%.6f" % p.predicted_sampling, "%.6f" % p.predicted_map,
                     "%.6f" % p.measured_sampling, "%.6f" % p.measured_map, "%.4f" % ratio(p, odd_factor(p)), "%.4f" % ratio(p, own(p))])
    lines += ["", "the checking half's even pairs under their measure with the own factor:"]
    for p in even:
        if p.half == "checking" and ratio(p, own(p)) < 1:
            lines.append("  %s n=%d @%d: %.2f (sampling part %.2f of its measure)" % (p.scene, p.n, p.map_size, ratio(p, own(p)), own(p) * p.predicted_sampling / p.measured_sampling))
    # Where auto would take an even side: its calibrated prediction against the odd side below it
    # at the same maps. Where the even side is predicted higher, the cheaper odd side meets any
    # target it meets.
    below = {(p.scene, p.n, p.map_size): p for p in odd}
    both = [(p, below[(p.scene, p.n - 1, p.map_size)]) for p in even if (p.scene, p.n - 1, p.map_size) in below]
    higher = sum(ratio(e, own(e)) * e.measured_rmse > ratio(o, odd_factor(o)) * o.measured_rmse for e, o in both)
    lines += ["", f"even side predicted above the odd side below it: {higher} of {len(both)} (scene, side, map size)"]
    return "\n".join(lines), rows, fit


def stretch_cost(rows: Table) -> str:
    """What a stretch of the factors costs ``auto``: rows of ``auto:target=T/s`` timed beside
    their oracle at T (``measured_over_target`` against T, ``time_over_oracle``).

    Args:
        rows: The rows (stretch-cost.csv).

    Returns:
        One line: measured/T's range, the rows within the promise's time ratio, the median ratio.
    """
    ratio = engine.promise().time_ratio
    m = [r.number("measured_over_target") for r in rows]
    t = [r.number("time_over_oracle") for r in rows]
    return (f"measured RMSE {min(m):.2f}–{max(m):.2f} T, time ≤ {ratio:g} × the oracle's on {sum(x <= ratio for x in t)} of {len(t)} rows, "
            f"median {median(t):.2f}")
