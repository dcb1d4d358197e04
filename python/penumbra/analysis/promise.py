"""``auto``'s rows against its promise (docs/budget.md §5): measured RMSE at most T, what each
row reported, and its time over the oracle's, counted as the promise asks
(:func:`penumbra.analysis.engine.promise`).

Rows come from a frontier's ``auto`` lines (:func:`frontier_rows`) or from a retake's CSV rows
(:func:`retake_rows`, written by :mod:`penumbra.analysis.retake`); both become
:class:`BudgetRow`, and :func:`count` counts either.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Optional

from . import engine
from .frontier import Frontier
from .rows import Row, RowError, Table
from .stats import median

NONE_REACHES = "none reaches it"


@dataclass(frozen=True)
class PairedChoice:
    """What ``auto`` chose under its oracle's maps, where that differs from its row's render."""

    choice: str
    maps: int
    measured_over_target: float
    met: bool


@dataclass(frozen=True)
class BudgetRow:
    """One ``auto:target=T`` row against its oracle.

    Attributes:
        scene: The scene.
        target: T.
        choice: The grid (``regular:n=5,layout=centred @ 512``) or the filter it rendered.
        maps: Its maps.
        rmse: Its measured RMSE.
        met: Whether its record reported T met.
        predicted: The predicted RMSE it reported (the best predicted where out of reach).
        search_ms: The tries of the frame that chose.
        oracle: The oracle's name, None where no fixed setting reaches T.
        oracle_maps: The oracle's maps.
        time_over_oracle: Side by side with the oracle, None where unpaired or no oracle.
        same_v: The fixed setting of the frontier whose V is the row's, '' where none is.
        names_best: Reported not met and named the best predicted error.
        oracle_same: The oracle rendered again read the frontier's RMSE bit for bit (retakes).
        paired: The choice under the oracle's maps where it differs from the row's (retakes).
    """

    scene: str
    target: float
    choice: str
    maps: int
    rmse: float
    met: bool
    predicted: float
    search_ms: float
    oracle: Optional[str]
    oracle_maps: Optional[int]
    time_over_oracle: Optional[float]
    same_v: str
    names_best: bool
    oracle_same: Optional[bool] = None
    paired: Optional[PairedChoice] = None

    @property
    def measured_over_target(self) -> float:
        """Measured RMSE over T."""
        return self.rmse / self.target


def _ratio(text: Optional[str]) -> Optional[float]:
    # paired.sh wrote `failed: …` where the window failed.
    if not text or text.startswith("failed"):
        return None
    return float(text)


def frontier_rows(frontiers: Iterable[Frontier], paired: Optional[Table] = None) -> list[BudgetRow]:
    """The ``auto`` rows of frontiers, with time/oracle from a table of side-by-side windows
    (``scene``, ``target``, ``time_over_oracle``) where the frontier did not pair them itself.

    Args:
        frontiers: One frontier per scene.
        paired: The side-by-side windows, or None to read the rows' own ``paired``.

    Returns:
        The rows, frontier by frontier in file order.
    """
    windows: dict[tuple[str, float], Row] = {}
    for p in paired or []:
        windows[(p.text("scene"), p.number("target"))] = p
    out = []
    for f in frontiers:
        for b in f.budget_rows("auto"):
            if b.budget is None or b.target is None:
                raise RowError(f"{f.table.path}:{b.row.line}: an auto row without its reading or target")
            if paired is not None:
                window = windows.get((b.scene, b.target))
                ratio = _ratio(window.optional_text("time_over_oracle")) if window is not None else None
            else:
                ratio = b.paired.ms / b.paired.oracle_ms if b.paired else None
            o = f.oracle(b)
            same = f.same_v(b.maps, b.rmse)
            out.append(BudgetRow(
                scene=b.scene, target=b.target, choice="", maps=b.maps, rmse=b.rmse, met=b.budget.target_met,
                predicted=b.budget.predicted, search_ms=b.budget.search_ms, oracle=b.oracle,
                oracle_maps=o.maps if o else None, time_over_oracle=ratio, same_v=same.name if same else "",
                names_best=not b.budget.target_met,
            ))
    return out


def retake_rows(paired: Table, alone: Optional[Table], frontiers: Mapping[str, Frontier]) -> list[BudgetRow]:
    """A retake's rows (:mod:`penumbra.analysis.retake`): each row's figures from its render at
    the frontier's first map size (``alone`` where the oracle's maps differ), time/oracle from the
    paired window where ``auto`` rendered the same maps there.

    Args:
        paired: The rows rendered beside their oracles (and the unreachable ones alone).
        alone: The rows rendered alone at 512² where the oracle's maps are not 512², or None.
        frontiers: Each scene's frontier, by scene.

    Returns:
        The rows, by scene and then T descending.

    Raises:
        RowError: A row whose render failed.
    """
    def key(r: Row) -> tuple[str, float]:
        return (r.text("scene"), r.number("target"))

    by_alone = {key(r): r for r in alone or []}
    out = []
    for p in paired:
        r = by_alone.get(key(p), p)
        if not r.has("maps") or not p.has("maps"):
            raise RowError(f"{p.path}:{p.line}: {key(p)[0]} at {key(p)[1]} failed: {r.optional_text('out_of_reach')} {p.optional_text('out_of_reach')}")
        f = frontiers[r.text("scene")]
        reached = p.text("oracle") != NONE_REACHES
        same_maps = p.integer("maps") == r.integer("maps")
        same = f.same_v(r.integer("maps"), r.number("rmse"))
        out.append(BudgetRow(
            scene=r.text("scene"), target=r.number("target"), choice=r.text("choice"), maps=r.integer("maps"), rmse=r.number("rmse"),
            met=r.flag("target_met"), predicted=r.number("predicted_rmse"), search_ms=r.number("search_ms"),
            oracle=p.text("oracle") if reached else None, oracle_maps=p.integer("oracle_maps") if reached else None,
            time_over_oracle=p.number("time_over_oracle") if reached and same_maps else None,
            same_v=same.name if same else "", names_best=_names_best(r),
            oracle_same=reached and p.number("oracle_rmse") == p.number("frontier_oracle_rmse"),
            paired=None if p is r else PairedChoice(p.text("choice"), p.integer("maps"), p.number("rmse") / p.number("target"), p.flag("target_met")),
        ))
    return sorted(out, key=lambda b: (b.scene, -b.target))


def _names_best(r: Row) -> bool:
    # Rows of 9f4717b carry the out-of-reach line auto printed; later rows its record's
    # best predicted error, where it reported T not met.
    if r.has("out_of_reach"):
        return "the best predicted is" in r.text("out_of_reach")
    return not r.flag("target_met") and r.has("predicted_rmse")


@dataclass(frozen=True)
class Counts:
    """The counts against the promise.

    Attributes:
        rows: Every row.
        under: Rows measuring at most T.
        reached: Rows some fixed setting of the frontier reaches (with an oracle).
        reached_under: Of those, the rows measuring at most T.
        false_met: Rows reported met while measuring over T.
        unreachable: Rows reported not met.
        names_best: Of those, the rows that named the best predicted error.
        timed: Rows with an oracle and a side-by-side time.
        untimed: Rows with an oracle but no side-by-side time.
        quick: Timed rows within the promise's time ratio.
        promise: The promise counted against.
    """

    rows: Sequence[BudgetRow]
    under: int
    reached: Sequence[BudgetRow]
    reached_under: int
    false_met: Sequence[BudgetRow]
    unreachable: Sequence[BudgetRow]
    names_best: int
    timed: Sequence[BudgetRow]
    untimed: int
    quick: int
    promise: engine.Promise = field(repr=False)

    @property
    def median_ratio(self) -> float:
        """The median time/oracle of the timed rows (NaN where none is timed)."""
        ratios = [r.time_over_oracle for r in self.timed if r.time_over_oracle is not None]
        return median(ratios) if ratios else float("nan")

    def table(self) -> str:
        """The counts as README.md's table rows (count, rows, the promise)."""
        n, p = len(self.rows), self.promise
        reached = len(self.reached)
        untimed = f" ({self.untimed} unpaired)" if self.untimed else ""

        def pct(k: int, of: int) -> str:
            return f"{100 * k / of:.0f}%" if of else "-"

        return "\n".join([
            f"| measured RMSE ≤ T, all rows | {self.under} of {n} ({pct(self.under, n)}) | {100 * p.met_share:.0f}% |",
            f"| measured RMSE ≤ T, rows some fixed setting of the run reaches | {self.reached_under} of {reached} ({pct(self.reached_under, reached)}) | {100 * p.met_share:.0f}% |",
            f"| reported met while measured over T | {len(self.false_met)} | 0 |",
            f"| reported `not met`, naming the best predicted error | {self.names_best} of {len(self.unreachable)} (of {n} rows) | every unreachable row |",
            f"| time ≤ {p.time_ratio:g} × the oracle's, side by side (rows with an oracle) | {self.quick} of {len(self.timed)} "
            f"({pct(self.quick, len(self.timed))}), median {self.median_ratio:.2f}{untimed} | {100 * p.time_share:.0f}% |",
        ])


def count(rows: Sequence[BudgetRow]) -> Counts:
    """Counts rows against the promise.

    Args:
        rows: The rows; at least one with an oracle and a time.

    Returns:
        The counts.
    """
    p = engine.promise()
    reached = [r for r in rows if r.oracle]
    timed = [r for r in reached if r.time_over_oracle is not None]
    unreachable = [r for r in rows if not r.met]
    return Counts(
        rows=list(rows),
        under=sum(r.rmse <= r.target for r in rows),
        reached=reached,
        reached_under=sum(r.rmse <= r.target for r in reached),
        false_met=[r for r in rows if r.met and r.rmse > r.target],
        unreachable=unreachable,
        names_best=sum(r.names_best for r in unreachable),
        timed=timed,
        untimed=len(reached) - len(timed),
        quick=sum(r.time_over_oracle is not None and r.time_over_oracle <= p.time_ratio for r in timed),
        promise=p,
    )


def rows_table(rows: Sequence[BudgetRow]) -> str:
    """README.md's rows table, one line per row.

    Args:
        rows: The rows.

    Returns:
        The table with its header.
    """
    lines = ["| scene | T | choice | maps | measured/T | reported | search ms | same V as | oracle (maps) | time/oracle |",
             "|---|---:|---|---:|---:|---|---:|---|---|---:|"]
    for r in rows:
        rep = f"met ({r.predicted:.4f})" if r.met else f"not met: best predicted {r.predicted:.4f}"
        o = f"{r.oracle} ({r.oracle_maps})" if r.oracle else NONE_REACHES
        ratio = f"{r.time_over_oracle:.2f}" if r.time_over_oracle is not None else "-"
        lines.append(f"| {r.scene} | {r.target} | {r.choice.replace(',layout=centred', '')} | {r.maps} | {r.measured_over_target:.2f} | {rep} | "
                     f"{r.search_ms:.0f} | {r.same_v or 'outside the run'} | {o} | {ratio} |")
    return "\n".join(lines)


def both_promises(measured_over_target: Optional[float], time_over_oracle: Optional[float]) -> bool:
    """Both promises on one row: measured at most T, time within the promise's ratio.

    Args:
        measured_over_target: Measured RMSE over T.
        time_over_oracle: Time over the oracle's.

    Returns:
        Whether both hold (False where either is unknown).
    """
    if measured_over_target is None or time_over_oracle is None:
        return False
    return measured_over_target <= 1 and time_over_oracle <= engine.promise().time_ratio


def report(rows: Sequence[BudgetRow]) -> str:
    """The counts, the rows that break a promise, and the rows table, as README.md quotes them.

    Args:
        rows: The rows (:func:`frontier_rows` or :func:`retake_rows`).

    Returns:
        The report.
    """
    c = count(rows)
    ratio = c.promise.time_ratio
    lines = [c.table(), "",
             f"false met: {[(r.scene, r.target, round(r.measured_over_target, 2)) for r in c.false_met]}",
             f"over {ratio:g} × the oracle: {[(r.scene, r.target, round(r.time_over_oracle, 2)) for r in c.timed if r.time_over_oracle is not None and r.time_over_oracle > ratio]}"]
    if rows and rows[0].oracle_same is not None:
        lines.append(f"oracle rendered again at the frontier's RMSE, bit for bit: {sum(bool(r.oracle_same) for r in c.reached)} of {len(c.reached)}")
        for r in rows:
            if r.paired and (r.paired.choice, r.paired.maps) != (r.choice, r.maps):
                p = r.paired
                lines.append(f"{r.scene} at {r.target}: under the oracle's maps auto took {p.choice} ({p.maps} maps, {p.measured_over_target:.2f} T, "
                             f"{'met' if p.met else 'not met'}), at 512² {r.choice} ({r.maps} maps)" + ("" if r.time_over_oracle is not None else ": time/oracle left out"))
    return "\n".join(lines + ["", rows_table(rows)])


def frontier_table(frontiers: Iterable[Frontier]) -> list[list[object]]:
    """A frontier's ``auto`` rows as one CSV table (rows.csv): each row's figures, what it
    reported, and its oracle's from the same frontier's windows.

    Args:
        frontiers: One frontier per scene.

    Returns:
        Rows under :data:`FRONTIER_TABLE_HEADER`.
    """
    out: list[list[object]] = []
    for f in frontiers:
        for b in f.budget_rows("auto"):
            assert b.budget is not None and b.target is not None
            o = f.oracle(b)
            out.append([b.scene, b.target, b.maps, b.rmse, b.rmse / b.target, "true" if b.budget.target_met else "false", b.budget.predicted, b.frame_ms,
                        b.budget.search_ms, b.budget.tries, b.oracle or NONE_REACHES, o.rmse if o else "", o.frame_ms if o else "",
                        b.frame_ms / o.frame_ms if o else ""])
    return out


FRONTIER_TABLE_HEADER = ["scene", "target", "maps", "rmse", "measured_over_target", "target_met", "predicted", "median_ms", "search_ms", "tries", "oracle",
                         "oracle_rmse", "oracle_ms", "time_over_oracle"]


def stretch_report(sweep: Mapping[float, Table]) -> str:
    """``auto``'s two promises against stretches s of its calibrated factors: each stretch's
    retake rows (``auto:target=T/s`` against the same rows, oracles and T, every row from its
    paired window) counted; then per row the stretches at which both promises hold.

    Args:
        sweep: Each stretch's retake rows; s = 1 among them.

    Returns:
        The report, as README.md quotes it.
    """
    ratio = engine.promise().time_ratio
    by = {s: {(r.text("scene"), r.number("target")): r for r in t} for s, t in sweep.items()}
    stretches = sorted(by)
    base = by[1.0]
    reached = [k for k in sorted(base) if base[k].text("oracle") != NONE_REACHES]

    def num(r: Optional[Row], key: str) -> Optional[float]:
        return r.optional_number(key) if r is not None else None

    def both(r: Optional[Row]) -> bool:
        return both_promises(num(r, "measured_over_target"), num(r, "time_over_oracle"))

    lines = [f"| stretch s | rows | measured <= T (reached rows) | time <= {ratio:g} x oracle | both | reported met over T | median time/oracle |",
             "|---:|---:|---:|---:|---:|---:|---:|"]
    for s in stretches:
        got = by[s]
        have = [k for k in reached if k in got and got[k].has("maps")]
        under = sum(1 for k in have if got[k].number("measured_over_target") <= 1)
        ratios = [x for x in (num(got[k], "time_over_oracle") for k in have) if x is not None]
        fast = sum(1 for x in ratios if x <= ratio)
        ok = sum(1 for k in have if both(got[k]))
        over = sum(1 for k in got if got[k].has("maps") and got[k].flag("target_met") and got[k].number("measured_over_target") > 1)
        lines.append(f"| {s:g} | {len(have)} of {len(reached)} | {under} ({100 * under / len(have):.0f}%) | {fast} of {len(ratios)} ({100 * fast / len(ratios):.0f}%) "
                     f"| {ok} ({100 * ok / len(have):.0f}%) | {over} of {len(got)} | {median(ratios):.2f} |")
    lines += ["", "| scene | T | oracle | " + " | ".join(f"s = {s:g}: measured/T, time/oracle" for s in stretches) + " | stretches serving both |",
              "|---|---:|---|" + "---|" * len(stretches) + "---|"]
    none = 0
    for k in reached:
        cells, serve = [], []
        for s in stretches:
            r = by[s].get(k)
            m, t = num(r, "measured_over_target"), num(r, "time_over_oracle")
            cells.append("-" if m is None else f"{m:.2f}, {t:.2f}" if t is not None else f"{m:.2f}, unpaired")
            if both(r):
                serve.append(f"{s:g}")
        none += not serve
        lines.append(f"| {k[0]} | {k[1]:g} | {base[k].text('oracle')} | " + " | ".join(cells) + f" | {', '.join(serve) or 'none'} |")
    n = len(reached)
    lines += ["", f"rows no stretch serves: {none} of {n}; at most {n - none} of {n} ({100 * (n - none) / n:.0f}%) can keep both promises at any one stretch of these"]
    return "\n".join(lines)


BEFORE_AFTER_HEADER = ["scene", "target", "before_maps", "before_over_t", "before_met", "before_time_over_oracle", "after_maps", "after_over_t", "after_met",
                       "after_oracle", "after_time_over_oracle"]


def before_after(before: Sequence[BudgetRow], after: Sequence[BudgetRow]) -> tuple[str, list[list[object]]]:
    """The same rows on two builds: each row of ``after`` beside the row of ``before`` at the same
    scene and T, and both builds' counts.

    Args:
        before: The earlier build's rows.
        after: The later build's rows (each must have its row in ``before``).

    Returns:
        README.md's table with both counts, and rows under :data:`BEFORE_AFTER_HEADER`.
    """
    ratio = engine.promise().time_ratio
    by = {(r.scene, r.target): r for r in before}
    pairs = [(by[(a.scene, a.target)], a) for a in after]

    def f4(x: Optional[float]) -> str:
        return "" if x is None else f"{x:.4f}"

    def f2(x: Optional[float]) -> str:
        return "–" if x is None else f"{x:.2f}"

    rows: list[list[object]] = [[a.scene, f4(a.target), b.maps, f4(b.measured_over_target), b.met, f4(b.time_over_oracle), a.maps, f4(a.measured_over_target),
                                 a.met, a.oracle or "", f4(a.time_over_oracle)] for b, a in pairs]
    lines = ["| scene | T | before: maps | measured/T | time/oracle | after: maps | measured/T | time/oracle |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for b, a in pairs:
        lines.append(f"| {a.scene} | {a.target} | {b.maps}{'' if b.met else ' (not met)'} | {b.measured_over_target:.2f} | {f2(b.time_over_oracle)} | "
                     f"{a.maps}{'' if a.met else ' (not met)'} | {a.measured_over_target:.2f} | {f2(a.time_over_oracle)} |")
    lines.append("")
    for side, k in (("before", 0), ("after", 1)):
        rs = [p[k] for p in pairs]
        under = sum(r.measured_over_target <= 1 for r in rs)
        ratios = [r.time_over_oracle for r in rs if r.time_over_oracle is not None]
        lines.append(f"{side}: measured ≤ T on {under} of {len(rs)}; time ≤ {ratio:g} × oracle on {sum(x <= ratio for x in ratios)} of {len(ratios)}, median {median(ratios):.2f}")
    return "\n".join(lines), rows
