"""One reader for every rows file of ``results/``: CSV with a header line, or JSON Lines.

A row's columns are read by name and typed on read (``row.number("rmse")``), so a missing or
malformed value is one :class:`RowError` naming the file, the line and the column, never a
``KeyError`` deep in an analysis. A JSON Lines row's nested keys read with dots
(``row.number("metrics.rmse")``, ``row.flag("budget.target_met")``). A CSV value is text until a
typed read converts it; an empty cell, like a JSON ``null``, is a missing value.

Every rows file the lab writes carries the same core keys (``scene``, ``spec``, ``method``,
``params``, ``maps``, ``map_size``, ``rmse``, ``frame_ms``, ``adapter``, ``version``, ``target``;
docs/formats.md); a row written before them is read under its old names (:data:`OLD_NAMES`).
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import IO, Any, Callable, Optional, TypeVar, Union, overload

PathLike = Union[str, Path]

#: The keys every study's row shares (the lab's ``RowCore``, docs/formats.md) under the names
#: rows written before the one schema used: a read of ``maps`` in such a row finds
#: ``shadow_maps``, as the lab reads it.
OLD_NAMES: dict[str, tuple[str, ...]] = {
    "maps": ("shadow_maps",),
    "map_size": ("shadow_map_size",),
    "frame_ms": ("total_ms",),
    "frame_ms_min": ("total_ms_min",),
    "frame_ms_max": ("total_ms_max",),
    "frame_ms_runs": ("total_ms_runs",),
    "rmse": ("metrics.rmse", "measured_rmse"),
}
T = TypeVar("T")
D = TypeVar("D")


#: The core keys a row written before them lacks and the reader derives (``Row._derived``).
DERIVED = ("method", "params", "target")


def asked(value: float) -> float:
    """A target as it was asked: the methods keep T as a 32-bit float, which JSON widens
    (0.03 reads 0.029999999329447746); its shortest decimal is what was written.

    Args:
        value: The widened value.

    Returns:
        The value as asked.
    """
    import numpy

    return float(str(numpy.float32(value)))


class RowError(ValueError):
    """A rows file that does not hold what its reader asks for; the message names the file, the
    line and the column."""


class Row:
    """One row of a rows file, its columns by name.

    Attributes:
        path: The file the row came from (``-`` for standard input).
        line: The row's line number in that file (1 is a CSV file's header).
    """

    __slots__ = ("_values", "path", "line")

    def __init__(self, values: Mapping[str, Any], path: str = "<rows>", line: int = 0) -> None:
        self._values = dict(values)
        self.path = path
        self.line = line

    def _where(self, name: str) -> str:
        return f"{self.path}:{self.line}: column {name!r}"

    def _lookup(self, name: str) -> Any:
        value = self._path(name)
        for old in OLD_NAMES.get(name, ()) if value is None else ():
            value = self._path(old)
            if value is not None:
                break
        if value is None and (name in DERIVED or name.startswith("params.")):
            value = self._derived(name)
        return value

    def _derived(self, name: str) -> Any:
        """``method``, ``params`` (or one of them, ``params.n``) or ``target`` of a row written
        before the core keys: from its ``params``, else from the engine's parse of its ``spec``
        (never from the spec's text)."""
        method, params = self._path("method"), self._path("params")
        if not isinstance(params, Mapping) or (name == "method" and method is None):
            spec = self._path("spec")
            if not isinstance(spec, str) or not spec:
                return None
            from . import engine
            from .. import PenumbraError

            try:
                parsed = engine.method_params(spec)
            except PenumbraError:
                return None
            method, params = parsed.pop("method"), parsed
        if name == "method":
            return method
        if name == "params":
            return params
        if name.startswith("params."):
            return params.get(name[len("params."):])
        t = params.get("target")
        return None if t is None else asked(float(t))

    def _path(self, name: str) -> Any:
        if name in self._values:
            return self._values[name]
        value: Any = self._values
        for part in name.split("."):
            if not isinstance(value, Mapping) or part not in value:
                return None
            value = value[part]
        return value

    def has(self, name: str) -> bool:
        """Whether the column is present with a value (not empty, not ``null``).

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            True where a typed read of the column would find a value.
        """
        value = self._lookup(name)
        return value is not None and value != ""

    def raw(self, name: str) -> Any:
        """The column's value as stored: text for CSV, any JSON value for JSON Lines.

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The value, or None where the column is missing, empty or ``null``.
        """
        value = self._lookup(name)
        return None if value == "" else value

    def _required(self, name: str) -> Any:
        value = self.raw(name)
        if value is None:
            raise RowError(f"{self._where(name)}: missing")
        return value

    def text(self, name: str) -> str:
        """The column as text.

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The value; a JSON number or boolean as JSON writes it.

        Raises:
            RowError: The column is missing.
        """
        value = self._required(name)
        if isinstance(value, str):
            return value
        return json.dumps(value)

    def optional_text(self, name: str) -> Optional[str]:
        """The column as text, or None where it is missing.

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The text, or None.
        """
        return self.text(name) if self.has(name) else None

    def number(self, name: str) -> float:
        """The column as a float.

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The value.

        Raises:
            RowError: The column is missing or not a number.
        """
        value = self._required(name)
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise RowError(f"{self._where(name)}: {value!r} is not a number")
        try:
            return float(value)
        except ValueError:
            raise RowError(f"{self._where(name)}: {value!r} is not a number") from None

    def optional_number(self, name: str) -> Optional[float]:
        """The column as a float, or None where it is missing.

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The value, or None.

        Raises:
            RowError: The column holds something that is not a number.
        """
        return self.number(name) if self.has(name) else None

    def integer(self, name: str) -> int:
        """The column as an integer.

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The value.

        Raises:
            RowError: The column is missing or not a whole number.
        """
        x = self.number(name)
        if not math.isfinite(x) or x != int(x):
            raise RowError(f"{self._where(name)}: {self.raw(name)!r} is not a whole number")
        return int(x)

    def flag(self, name: str) -> bool:
        """The column as a boolean: JSON ``true``/``false``, or the text ``true``/``false``
        (``True``/``False`` as Python's csv writes them).

        Args:
            name: The column, nested keys joined by dots.

        Returns:
            The value.

        Raises:
            RowError: The column is missing or not a boolean.
        """
        value = self._required(name)
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.lower() in ("true", "false"):
            return value.lower() == "true"
        raise RowError(f"{self._where(name)}: {value!r} is not true or false")

    def get(self, name: str, read: Callable[[str], T], default: D) -> Union[T, D]:
        """A typed read with a default where the column is missing.

        Args:
            name: The column, nested keys joined by dots.
            read: The typed read, e.g. ``row.number``.
            default: What a missing column gives.

        Returns:
            ``read(name)``, or ``default``.
        """
        return read(name) if self.has(name) else default

    def as_dict(self) -> dict[str, Any]:
        """The row's columns as a plain dict (a copy)."""
        return dict(self._values)

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and self.has(name)

    def __repr__(self) -> str:
        return f"Row({self.path}:{self.line})"


class Table(Sequence[Row]):
    """The rows of one file, in file order.

    Attributes:
        path: The file (``-`` for standard input).
        columns: The CSV header, or every top-level key seen in a JSON Lines file, in order.
    """

    def __init__(self, rows: Sequence[Row], path: str, columns: Sequence[str]) -> None:
        self._rows = list(rows)
        self.path = path
        self.columns = list(columns)

    @overload
    def __getitem__(self, i: int) -> Row: ...

    @overload
    def __getitem__(self, i: slice) -> Sequence[Row]: ...

    def __getitem__(self, i: Union[int, slice]) -> Union[Row, Sequence[Row]]:
        return self._rows[i]

    def __len__(self) -> int:
        return len(self._rows)

    def __iter__(self) -> Iterator[Row]:
        return iter(self._rows)

    def where(self, keep: Callable[[Row], bool]) -> list[Row]:
        """The rows ``keep`` accepts, in order."""
        return [r for r in self._rows if keep(r)]

    def builds(self) -> list[str]:
        """The git hashes of the builds the rows name in their own ``version`` column, in order of
        first appearance: JSON's ``{"crate": …, "git": …}`` or a CSV column of the hash.

        Returns:
            The distinct hashes; empty where no row carries a version.
        """
        seen: dict[str, None] = {}
        for r in self._rows:
            v = r.raw("version")
            if isinstance(v, Mapping):
                v = v.get("git")
            if isinstance(v, str) and v:
                seen.setdefault(v, None)
        return list(seen)


def build_line(tables: Iterable[Table]) -> str:
    """``build: HASH`` (or several, comma-separated) from the rows' own ``version`` columns, as a
    driver prints it; where no row carries one, says so, so a reader looks in the README.

    Args:
        tables: The rows files a driver read.

    Returns:
        One line.
    """
    seen: dict[str, None] = {}
    for t in tables:
        for b in t.builds():
            seen.setdefault(b, None)
    if not seen:
        return "build: not recorded in the rows (they predate the version column; the README names it)"
    return "build: " + ", ".join(seen)


def _kind(path: str) -> str:
    if path.endswith(".jsonl") or path.endswith(".json"):
        return "jsonl"
    if path.endswith(".csv"):
        return "csv"
    raise RowError(f"{path}: not a rows file (.csv or .jsonl)")


def parse(text: str, path: str = "-", kind: str = "csv") -> Table:
    """Rows from text already read (standard input, a process's output).

    Args:
        text: The file's content.
        path: What errors call it.
        kind: ``csv`` or ``jsonl``.

    Returns:
        The table.

    Raises:
        RowError: A ragged CSV row, or a JSON Lines line that is not an object.
    """
    if kind == "jsonl":
        rows: list[Row] = []
        columns: dict[str, None] = {}
        for i, line in enumerate(text.splitlines(), 1):
            if not line.strip():
                continue
            try:
                value = json.loads(line)
            except json.JSONDecodeError as e:
                raise RowError(f"{path}:{i}: not JSON ({e.msg})") from None
            if not isinstance(value, dict):
                raise RowError(f"{path}:{i}: not a JSON object")
            for k in value:
                columns.setdefault(k, None)
            rows.append(Row(value, path, i))
        return Table(rows, path, list(columns))
    if kind != "csv":
        raise RowError(f"{path}: kind {kind!r} is neither csv nor jsonl")
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None:
        raise RowError(f"{path}: empty, no header line")
    rows = []
    for values in reader:
        if not values:
            continue
        if len(values) != len(header):
            raise RowError(f"{path}:{reader.line_num}: {len(values)} values under a header of {len(header)}")
        rows.append(Row(dict(zip(header, values)), path, reader.line_num))
    return Table(rows, path, header)


def read(path: PathLike) -> Table:
    """Reads one rows file: ``.csv`` (a header line) or ``.jsonl``/``.json`` (one object a line);
    ``-`` reads CSV from standard input.

    Args:
        path: The file.

    Returns:
        Its rows.

    Raises:
        RowError: The file is missing, not a rows file, or malformed (naming file and line).
    """
    name = str(path)
    if name == "-":
        return parse(sys.stdin.read(), "-", "csv")
    kind = _kind(name)
    try:
        text = Path(name).read_text(encoding="utf-8")
    except OSError as e:
        raise RowError(f"{name}: {e.strerror or e}") from None
    return parse(text, name, kind)


def read_json(path: PathLike) -> Row:
    """Reads one JSON object file (a ``run.json``) as a row.

    Args:
        path: The file.

    Returns:
        The object as one row (line 1).

    Raises:
        RowError: The file is missing or not a JSON object.
    """
    name = str(path)
    try:
        value = json.loads(Path(name).read_text(encoding="utf-8"))
    except OSError as e:
        raise RowError(f"{name}: {e.strerror or e}") from None
    except json.JSONDecodeError as e:
        raise RowError(f"{name}: not JSON ({e.msg})") from None
    if not isinstance(value, dict):
        raise RowError(f"{name}: not a JSON object")
    return Row(value, name, 1)


def write_csv(out: IO[str], header: Sequence[str], rows: Iterable[Sequence[Any]]) -> None:
    """Writes a CSV table (``\\n`` line ends, quoted by the CSV rules).

    Args:
        out: An open text stream.
        header: The column names.
        rows: One sequence of values per row, as wide as the header.
    """
    w = csv.writer(out, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        if len(r) != len(header):
            raise ValueError(f"a row of {len(r)} values under a header of {len(header)}")
        w.writerow(r)


def write_csv_file(path: PathLike, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> None:
    """Writes a CSV table to a file (as :func:`write_csv`).

    Args:
        path: The file, replaced.
        header: The column names.
        rows: One sequence of values per row, as wide as the header.
    """
    with open(path, "w", encoding="utf-8", newline="") as f:
        write_csv(f, header, rows)
