"""The error budget's other analyses (docs/budget.md): what a map of each size adds to a frame
and why ``auto``'s price of it does or does not move its choice (results/budget-prices/), and a
finer grid as a truth-free reference for its choice (results/budget-reference/).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

from . import engine
from .frontier import Frontier, Setting
from .rows import PathLike, Row, Table, read, read_json
from .stats import median

# --- budget-prices --------------------------------------------------------------------------

FRAME_SPLIT_HEADER = ["round", "scene", "n", "map_size", "total_ms", "shadow_raster_ms", "shade_ms", "gbuffer_ms", "readback_ms"]


def frame_split_row(round_: int, n: int, run: Row) -> list[object]:
    """One render's row of frame-split.csv: where its frame's time went, by stage.

    Args:
        round_: The round.
        n: The grid's side.
        run: The render's run.json.

    Returns:
        The row under :data:`FRAME_SPLIT_HEADER`.
    """
    return [round_, run.text("scene"), n, run.integer("shadow_map_size"), run.number("total_ms"),
            *(run.number(f"stages_ms.{s}") for s in ("shadow_raster", "shade", "gbuffer", "readback"))]


def frame_split(binary: str, scenes: Sequence[str], sides: Sequence[int], sizes: Sequence[int], rounds: int, resolution: int) -> list[list[object]]:
    """Renders ``regular:n=N,layout=centred`` of each side at each map size on each scene, in
    interleaved rounds, each render with its stage timing (:func:`frame_split_row`).

    Args:
        binary: The ``penumbra`` binary.
        scenes: The scenes.
        sides: The grids' sides.
        sizes: The map sides.
        rounds: The rounds.
        resolution: The screen's side.

    Returns:
        Rows under :data:`FRAME_SPLIT_HEADER`; a failed render is left out and said on stderr.
    """
    from . import binary as bin_

    rows = []
    with bin_.scratch() as tmp:
        for r in range(1, rounds + 1):
            for scene in scenes:
                for n in sides:
                    for z in sizes:
                        run = bin_.render(binary, scene, f"regular:n={n},layout=centred", tmp / "r", {"resolution": resolution, "shadow_map_size": z})
                        if run.ok:
                            rows.append(frame_split_row(r, n, run.run_json()))
                        else:
                            print(f"failed: {scene} {n} {z}: {run.last_line()}", file=sys.stderr)
    return rows


def frame_split_table(rows: Table) -> str:
    """The medians of frame-split.csv per (scene, side, map size), ms: total, raster, raster per
    map, shade, G-buffer.

    Args:
        rows: frame-split.csv.

    Returns:
        README.md's table.
    """
    g: dict[tuple[str, int, int], list[Row]] = {}
    for r in rows:
        g.setdefault((r.text("scene"), r.integer("n"), r.integer("map_size")), []).append(r)
    lines = ["| scene | n | maps | total | raster | raster per map | shade | G-buffer |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for (scene, n, z), rs in g.items():
        def m(key: str) -> float:
            return median(r.number(key) for r in rs)

        lines.append(f"| {scene} | {n} | {z}² | {m('total_ms'):.0f} | {m('shadow_raster_ms'):.0f} | {m('shadow_raster_ms') / n / n:.1f} | {m('shade_ms'):.1f} | {m('gbuffer_ms'):.1f} |")
    return "\n".join(lines)


PRICES_HEADER = ["round", "build", "scene", "target", "process_s", "pricing_ms", "price_512", "price_1024", "price_2048", "chosen", "map_size", "maps", "total_ms"]


def prices_row(round_: int, build: str, target: float, seconds: float, run: Row) -> list[object]:
    """One ``auto:target=T`` render's row of prices.csv: the process's wall clock, the record's
    prices per map and its choice.

    Args:
        round_: The round.
        build: ``before`` or ``after``.
        target: T.
        seconds: The process's wall clock.
        run: The render's run.json.

    Returns:
        The row under :data:`PRICES_HEADER`.
    """
    m = "method_record"
    price = [run.get(f"{m}.map_cost.per_map.{z}", run.number, "") for z in (512, 1024, 2048)]
    chosen = run.text(f"{m}.renders") if run.has(f"{m}.renders") else run.text(f"{m}.chosen.spec")
    return [round_, build, run.text("scene"), target, seconds, run.get(f"{m}.map_cost.pricing_ms", run.number, ""), *price, chosen,
            run.integer(f"{m}.chosen.map_size"), run.integer("shadow_maps"), run.number("total_ms")]


def prices(builds: Mapping[str, str], rows: Sequence[tuple[str, float]], rounds: int, resolution: int, runs: Optional[PathLike]) -> list[list[object]]:
    """Each build's prices and choice, side by side: ``auto:target=T`` rendered alone by each
    build in turn, interleaved rounds, with the process's wall clock (:func:`prices_row`).

    Args:
        builds: ``before`` and ``after`` binaries, by name.
        rows: (scene, T) to render.
        rounds: The rounds.
        resolution: The screen's side.
        runs: Where the ``after`` build's run.json files go (``SCENE-T-ROUND.json``), or None.

    Returns:
        Rows under :data:`PRICES_HEADER`; a failed render is left out and said on stderr.
    """
    import shutil
    import time

    from . import binary as bin_

    out = []
    with bin_.scratch() as tmp:
        for r in range(1, rounds + 1):
            for scene, t in rows:
                for b, path in builds.items():
                    start = time.monotonic()
                    run = bin_.render(path, scene, f"auto:target={t:g}", tmp / "r", {"resolution": resolution})
                    if not run.ok:
                        print(f"failed: {b} {scene} {t:g}: {run.last_line()}", file=sys.stderr)
                        continue
                    out.append(prices_row(r, b, t, time.monotonic() - start, run.run_json()))
                    if b == "after" and runs is not None:
                        Path(runs).mkdir(parents=True, exist_ok=True)
                        shutil.copy(tmp / "r" / "run.json", Path(runs) / f"{scene}-{t:g}-{r}.json")
    return out


def paired_counts(paired: Table) -> str:
    """The table of time/oracle per row and build (``round``, ``build`` and a retake's columns;
    rows paired.sh wrote name auto's ``auto_maps``, ``auto_rmse``): each round's ratio and their
    median, before and after.

    Args:
        paired: The rows.

    Returns:
        README.md's table.
    """
    def col(r: Row, name: str) -> str:
        return name if r.has(name) else f"auto_{name}"

    g: dict[tuple[str, float], dict[str, list[Row]]] = {}
    for r in paired:
        g.setdefault((r.text("scene"), r.number("target")), {}).setdefault(r.text("build"), []).append(r)
    lines = ["| scene | T | auto maps | measured/T | oracle (maps) | before | after |", "|---|---:|---:|---:|---|---:|---:|"]
    for (scene, t), b in g.items():
        a = b["after"][0]

        def cell(k: str) -> str:
            xs = [r.number("time_over_oracle") for r in b[k]]
            return " / ".join("%.2f" % x for x in xs) + " (median %.2f)" % median(xs)

        lines.append(f"| {scene} | {t:g} | {a.text(col(a, 'maps'))} | {a.number(col(a, 'rmse')) / t:.2f} | {a.text('oracle')} ({a.text('oracle_maps')}) | {cell('before')} | {cell('after')} |")
    return "\n".join(lines)


WHY_HEADER = ["scene", "target", "try", "n", "map_size", "predicted", "size", "cheapest_n_meeting", "maps", "cost", "break_even_ratio_2048_over_1024",
              "priced_ratio"]


def why(run: Row) -> list[list[object]]:
    """Why a price does or does not move ``auto``'s choice: from each try of a run that missed T,
    the cheapest odd grid (3 to the run's ``max_n``) at each priced map size that ``auto``'s own
    law (:func:`penumbra.analysis.engine.predicted_at`) says meets T, its cost at the record's
    prices, and the price ratio of a 2048² map to a 1024² one above which the 1024² grid would be
    the cheaper.

    Args:
        run: An ``auto`` render's run.json.

    Returns:
        Rows under :data:`WHY_HEADER`.
    """
    rec = run.raw("method_record")
    t = float(rec["target"])
    prices = {int(k): float(v) for k, v in rec["map_cost"]["per_map"].items()}
    sides = list(range(3, run.integer("params.max_n") + 1, 2))
    out: list[list[object]] = []
    for k, p in enumerate(rec["tries"]):
        if p["predicted_rmse"] <= t:
            continue
        n, z = int(p["n"]), int(p["map_size"])
        light = engine.light_class_of_try(int(p["maps"]), n)
        best: dict[int, Optional[int]] = {}
        for z2 in [s for s in sorted(prices) if s >= z]:
            best[z2] = next((n2 for n2 in sides if n2 >= n and (n2, z2) != (n, z) and engine.predicted_at(light, n, z, p, n2, z2) <= t), None)
        b1, b2 = best.get(1024), best.get(2048)
        even = "%.2f" % (b1 ** 2 / b2 ** 2) if b1 and b2 else ""
        for z2, m in best.items():
            cost = "" if m is None else "%.0f" % (m * m * prices[z2])
            out.append([run.text("scene"), t, k, n, z, f"{p['predicted_rmse']:.4f}", z2, m or "none", "" if m is None else m * m, cost, even,
                        f"{prices.get(2048, 0) / prices.get(1024, 1):.2f}"])
    return out


# --- budget-reference -----------------------------------------------------------------------

RULES: Mapping[str, Callable[[float, float], float]] = {
    "triangle": lambda d, e: d + e,
    "quadrature": lambda d, e: math.sqrt(d * d + e * e),
    "as truth": lambda d, e: d,
}
REFERENCE_HEADER = ["scene", "target", "reference_rmse", "oracle", "oracle_rmse", "rule", "choice", "choice_rmse", "measured_over_target", "time_over_oracle"]


def reference_grid() -> str:
    """The finest grid ``auto`` may choose (its ``max_n`` centred at its ``max_size``), the reference R."""
    p = engine.method_params("auto")
    return f"regular:n={p['max_n']},layout=centred"


def _visibility(run: Path, spec: str) -> Any:
    """V of ``spec`` from a compare's folder: its row found by the engine's parse of the spec
    (labels leave defaults out), its ``visibility.exr`` beside the row's picture."""
    import numpy

    from .. import read_exr

    want = engine.method_params(spec)
    name = want.pop("method")
    row = next((r for r in read(run / "results.jsonl") if r.text("method") == name and r.raw("params") == want), None)
    if row is None:
        raise FileNotFoundError(f"{run}/results.jsonl: no row of {spec}")
    return numpy.asarray(read_exr(run / Path(row.text("images.visibility")).with_name("visibility.exr")), dtype=numpy.float64)


@dataclass(frozen=True)
class Candidate:
    """A setting of ``auto``'s ladder as the reference reads it."""

    setting: Setting
    d: float

    @property
    def label(self) -> str:
        return f"{self.setting.spec} @ {self.setting.map_size}"


def reference_rows(out: PathLike, scene: str, frontier: Frontier, ladder: Sequence[str], sizes: Sequence[int]) -> list[list[object]]:
    """A finer grid R as a truth-free reference for ``auto``'s choice: each candidate c of the
    ladder measured by its difference from R, d_c = RMSE(V_c − V_R); then, per target of the
    frontier's ``auto`` rows and per rule (:data:`RULES`: the triangle bound d_c + e_R, the
    quadrature sqrt(d_c² + e_R²), R as the truth d_c, each at most T), the cheapest candidate
    (by the frontier's time), its measured RMSE over T and its time over the oracle's. e_R, R's
    own error, is measured: an advantage no truth-free method has.

    Args:
        out: What the driver rendered: ``OUT/SCENE/{SIZE,SIZE-msm,ref}/`` compare folders and
            ``OUT/SCENE/SIZE/reference.{exr,json}``.
        scene: The scene.
        frontier: Its frontier (the candidates' times and RMSE, the oracles).
        ladder: The candidates' specs.
        sizes: Their map sizes.

    Returns:
        Rows under :data:`REFERENCE_HEADER`.
    """
    import numpy

    from .. import read_exr

    base = Path(out) / scene
    first = base / str(sizes[0])
    pixels = read_json(first / "reference.json").integer("geometry_pixels")
    truth = numpy.asarray(read_exr(first / "reference.exr"), dtype=numpy.float64)

    def rms(a: Any, b: Any) -> float:
        return float(numpy.sqrt(((a - b) ** 2).sum() / pixels))

    ref = _visibility(base / "ref", reference_grid())
    e_ref = rms(ref, truth)
    candidates = []
    for f in frontier.fixed:
        if f.spec not in ladder or f.map_size not in sizes:
            continue
        v = _visibility(base / (f"{f.map_size}-msm" if f.spec == "msm" else str(f.map_size)), f.spec)
        mine = rms(v, truth)
        # The EXR is V as rendered (f32): it must be the frontier's setting, to f32 rounding.
        if abs(mine - f.rmse) >= 1e-5 * max(1.0, f.rmse) + 1e-6:
            raise ValueError(f"{scene} {f.name}: RMSE {mine} from the render, {f.rmse} in the frontier: not the same setting")
        candidates.append(Candidate(f, rms(v, ref)))
    rows: list[list[object]] = []
    for b in frontier.budget_rows("auto"):
        t = b.target
        assert t is not None
        o = frontier.oracle(b)
        for rule, bound in RULES.items():
            ok = [c for c in candidates if bound(c.d, e_ref) <= t]
            c = min(ok, key=lambda c: c.setting.frame_ms) if ok else None
            rows.append([scene, t, f"{e_ref:.6f}", f"{o.spec} @ {o.map_size}" if o else "none reaches it", f"{o.rmse:.6f}" if o else "", rule,
                         c.label if c else "none meets it", f"{c.setting.rmse:.6f}" if c else "", f"{c.setting.rmse / t:.3f}" if c else "",
                         f"{c.setting.frame_ms / o.frame_ms:.3f}" if c and o else ""])
    return rows


def reference_counts(rows: Table) -> str:
    """Counts of the reference's rows per rule: rows some fixed setting reaches, the rule's choice
    at most T, within the promise's time ratio of the oracle, both, and rows where it finds nothing.

    Args:
        rows: The rows of :func:`reference_rows`.

    Returns:
        The report, as README.md quotes it.
    """
    ratio = engine.promise().time_ratio
    refs = {r.text("scene"): r.number("reference_rmse") for r in rows}
    lines = ["reference (17x17 centred at 2048²) RMSE per scene: " + ", ".join(f"{s} {e:.4f}" for s, e in sorted(refs.items())),
             f"| rule | rows reached | choice <= T | time <= {ratio:g} x oracle | both | nothing meets T |", "|---|---:|---:|---:|---:|---:|"]
    for rule in dict.fromkeys(r.text("rule") for r in rows):
        got = [r for r in rows if r.text("rule") == rule and r.text("oracle") != "none reaches it"]
        under = sum(1 for r in got if r.has("measured_over_target") and r.number("measured_over_target") <= 1)
        fast = sum(1 for r in got if r.has("time_over_oracle") and r.number("time_over_oracle") <= ratio)
        both = sum(1 for r in got if r.has("measured_over_target") and r.number("measured_over_target") <= 1 and r.number("time_over_oracle") <= ratio)
        none = sum(1 for r in got if r.text("choice") == "none meets it")
        n = len(got)
        lines.append(f"| {rule} | {n} | {under} ({100 * under / n:.0f}%) | {fast} ({100 * fast / n:.0f}%) | {both} ({100 * both / n:.0f}%) | {none} |")
    return "\n".join(lines)
