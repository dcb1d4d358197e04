"""Rows of ``penumbra compare`` (results.jsonl) as a small CSV table, by named columns:

    python3 -m penumbra.analysis.table OUT/*/results.jsonl --columns scene,setting,maps,rmse,median_ms,runs_ms

Named columns: ``scene``, ``setting`` (the method's label), ``target``, ``map_size`` (or
``shadow_map_size``),
``maps``, ``rmse`` (5 decimals), ``median_ms`` (1 decimal), ``ms`` (whole), ``runs_ms`` (each
timed frame, whole, joined by ``/``), ``shadow_raster_ms`` (1 decimal); any other name is the
row's own key, nested keys joined by dots (``params.centre_size``), as stored; ``NAME=KEY`` heads
the column of KEY with NAME (``centre_size=params.centre_size``).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Iterable, Sequence
from typing import Optional

from .frontier import target_of
from .rows import Row, RowError, read, write_csv

COLUMNS: dict[str, Callable[[Row], object]] = {
    "scene": lambda r: r.text("scene"),
    "setting": lambda r: r.text("label"),
    "target": lambda r: target_of(r),
    "shadow_map_size": lambda r: r.integer("map_size"),
    "map_size": lambda r: r.integer("map_size"),
    "maps": lambda r: r.integer("maps"),
    "rmse": lambda r: f"{r.number('rmse'):.5f}",
    "median_ms": lambda r: f"{r.number('frame_ms'):.1f}",
    "ms": lambda r: f"{r.number('frame_ms'):.0f}",
    "runs_ms": lambda r: "/".join(f"{x:.0f}" for x in r.raw("frame_ms_runs") or []),
    "shadow_raster_ms": lambda r: f"{r.number('stages_ms.shadow_raster'):.1f}",
}


def column(name: str) -> Callable[[Row], object]:
    """The getter of a named column, or of the row's own key.

    Args:
        name: A name of :data:`COLUMNS` or a (dotted) key.

    Returns:
        The getter; it raises :class:`~penumbra.analysis.rows.RowError` where the row lacks the key.
    """
    if name in COLUMNS:
        return COLUMNS[name]

    def get(r: Row) -> object:
        if not r.has(name):
            raise RowError(f"{r.path}:{r.line}: column {name!r}: missing")
        return r.raw(name)

    return get


def table(rows: Iterable[Row], columns: Sequence[str]) -> list[list[object]]:
    """The rows' named columns.

    Args:
        rows: compare's rows.
        columns: The column names.

    Returns:
        One list of values per row.
    """
    getters = [column(c) for c in columns]
    return [[g(r) for g in getters] for r in rows]


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command line: results.jsonl files to a CSV table on standard output.

    Args:
        argv: The arguments (``sys.argv[1:]`` by default).

    Returns:
        The exit status.
    """
    p = argparse.ArgumentParser(prog="python3 -m penumbra.analysis.table", description="compare's rows as a CSV table of named columns")
    p.add_argument("files", nargs="+", help="results.jsonl files, read in order")
    p.add_argument("--columns", required=True, help="comma-separated column names")
    a = p.parse_args(argv)
    named = [c.partition("=") for c in a.columns.split(",")]
    try:
        rows = [row for f in a.files for row in table(read(f), [key or name for name, _, key in named])]
    except RowError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    write_csv(sys.stdout, [name for name, _, _ in named], rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
