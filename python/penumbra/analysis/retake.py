"""Renders ``auto``'s rows of a frontier again on the current build, without a new frontier.

The fixed settings render the same V as on the build that took the frontier
(``scripts/same-v.sh``), so each row's oracle (its ``oracle``) stands, and only ``auto`` is
rendered:

- a row with an oracle: one ``penumbra compare`` renders ``auto:target=T`` and the oracle in one
  window under the oracle's map size, frames interleaved; time/oracle is the ratio of their
  median frame times, and the oracle's RMSE is rendered again beside the frontier's
  (``oracle_rmse`` against ``frontier_oracle_rmse``);
- a row no fixed setting reaches: ``auto:target=T`` alone at 512², one timed frame.

``alone=True`` renders, instead, the rows whose oracle's maps are not 512² alone at 512²: the
frontier renders its budget rows at its first map size, and a one-map filter renders at the
scene's, so there a filter's choice can differ from the paired window's
(:func:`penumbra.analysis.promise.retake_rows` takes each row's figures from these).
``stretch=s`` renders ``auto:target=T/s`` (the calibrated factors stretched by s) against the
same row, its oracle and T. What a row reports is its run.json's record (``target_met``,
``predicted_rmse``: the best predicted where out of reach; where ``auto`` decided by its certified
bound, that bound, and the decision's time in ``search_ms``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Optional

from . import binary as bin_
from .auto_record import AutoRecord
from .frontier import Frontier, Setting
from .promise import NONE_REACHES

HEADER = ["scene", "target", "maps", "choice", "rmse", "measured_over_target", "target_met", "predicted_rmse", "search_ms", "tries",
          "out_of_reach", "ms", "oracle", "oracle_maps", "oracle_rmse", "frontier_oracle_rmse", "oracle_ms", "time_over_oracle", "version"]
ALONE_SIZE = 512
REPEATS = 5


def _text(x: Any) -> Any:
    # The CSV's booleans as JSON writes them.
    return ("true" if x else "false") if isinstance(x, bool) else x


def retake_row(binary: str, frontier: Frontier, row: Setting, stretch: float = 1.0, alone: bool = False, repeats: int = REPEATS) -> Optional[list[Any]]:
    """Renders one ``auto`` row again (see the module's doc).

    Args:
        binary: The ``penumbra`` binary.
        frontier: The row's frontier.
        row: An ``auto`` budget row of it (rendered at the frontier's screen, its ``resolution``).
        stretch: Renders ``auto:target=T/stretch``.
        alone: Renders the row alone at 512² where its oracle's maps are not 512² (None for the others).
        repeats: Timed frames per method in a paired window.

    Returns:
        The CSV row under :data:`HEADER`, or None where ``alone`` skips it.
    """
    t = row.target
    assert t is not None, row
    spec = row.spec if stretch == 1 else f"auto:target={t / stretch!r}"
    oracle = frontier.oracle(row)
    unpaired = NONE_REACHES
    if alone:
        if oracle is None or oracle.map_size == ALONE_SIZE:
            return None
        oracle, unpaired = None, f"alone at {ALONE_SIZE}"
    size = oracle.map_size if oracle is not None else ALONE_SIZE
    methods = [spec] if oracle is None else [spec, oracle.spec]
    with bin_.scratch() as out:
        width, height = row.row.raw("resolution")
        r = bin_.compare(binary, row.scene, methods, out / "c", {"width": width, "height": height, "shadow_map_size": size}, repeats if oracle else 1)
        if not r.ok:
            failed = f"failed: {r.last_line()}".replace('"', "'")
            return [row.scene, t, "", "", "", "", "", "", "", "", failed, "", oracle.name if oracle else unpaired, "", "", "", "", "", ""]
        rows = r.results()
        a, b = rows[0], (rows[1] if len(rows) > 1 else None)
        m = r.run_json("images/auto*/run.json")
        rec = AutoRecord.read(m.raw("method_record"), "images/auto*/run.json")
        # What auto rendered: its own name for it, else the filter or the grid it chose; where
        # it decided by its certified bound, the bound is what it reports, and the decision's
        # time is part of its search; out of reach, the record's warning says so.
        chosen, reach = rec.choice(), rec.warning or ""
        rmse = a.number("rmse")
        return [
            row.scene, t, a.integer("maps"), chosen, rmse, rmse / t, _text(rec.target_met),
            rec.reported(), rec.search_ms(), len(rec.tries), reach, a.number("frame_ms"),
            oracle.name if b is not None and oracle else unpaired,
            b.integer("maps") if b is not None else "", b.number("rmse") if b is not None else "",
            oracle.rmse if oracle else "", b.number("frame_ms") if b is not None else "",
            a.number("frame_ms") / b.number("frame_ms") if b is not None else "", a.text("version.git"),
        ]


def retake(binary: str, frontiers: Sequence[Frontier], stretch: float = 1.0, alone: bool = False, repeats: int = REPEATS) -> list[list[Any]]:
    """Every ``auto`` row of each frontier, one after another (:func:`retake_row`).

    Args:
        binary: The ``penumbra`` binary.
        frontiers: The frontiers, one per scene.
        stretch: Renders ``auto:target=T/stretch``.
        alone: See :func:`retake_row`.
        repeats: Timed frames per method in a paired window.

    Returns:
        The CSV rows under :data:`HEADER`.
    """
    out = []
    for f in frontiers:
        for row in f.budget_rows("auto"):
            r = retake_row(binary, f, row, stretch, alone, repeats)
            if r is not None:
                out.append(r)
    return out
