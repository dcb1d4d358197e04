"""A frontier's rows (``frontier.jsonl``) as typed settings, and the oracle as the lab names it.

The oracle of a budget row (``auto:target=T``, ``regions:target=T``) is the cheapest fixed
setting of the same frontier whose measured RMSE is at most T; the setting it is matched with is
the cheapest whose RMSE is at most its own. ``penumbra frontier`` writes both into the row
(``oracle``, ``beaten_by``; ``lab/src/studies/frontier/``), so this module reads them and
computes neither: there is one oracle, the lab's.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Optional, Union, overload

from .rows import PathLike, Row, RowError, Table, read

BUDGET = "error budget"


def target_of(row: Row) -> Optional[float]:
    """A row's target T: its ``target`` column, which the lab writes in every row whose method
    has one (rows written before the column: the reader derives it, see
    :func:`~penumbra.analysis.rows.Row.raw`).

    Args:
        row: A frontier or compare row.

    Returns:
        T, or None for a method without a target.
    """
    return row.optional_number("target")


@dataclass(frozen=True)
class Paired:
    """A budget row and its oracle timed side by side (``budget::Paired``)."""

    ms: float
    oracle_ms: float


@dataclass(frozen=True)
class Reading:
    """What an ``auto`` row's own record said (``budget::Reading``)."""

    predicted: float
    target_met: bool
    search_ms: float
    tries: int


@dataclass(frozen=True)
class Setting:
    """One line of ``frontier.jsonl``.

    Attributes:
        scene: The scene.
        spec: The method spec as the grid writes it.
        method: The method's name.
        map_config: ``plain 512``, ``hybrid 2048→512``, …
        kind: ``regular centred``, …, ``error budget``.
        maps: Shadow maps of the judged frame.
        map_size: The map side the frame rendered.
        rmse: Measured RMSE of V.
        frame_ms: Median frame time.
        target: T for a budget row.
        oracle: A budget row's oracle (``spec @ map_config``), None where none reaches T.
        beaten_by: The setting the row is matched with (see the module's doc).
        failed: Why the setting failed at run time, or None.
        budget: An ``auto`` row's reading.
        paired: An ``auto`` row timed beside its oracle.
        row: The row it was read from.
    """

    scene: str
    spec: str
    method: str
    map_config: str
    kind: str
    maps: int
    map_size: int
    rmse: float
    frame_ms: float
    target: Optional[float]
    oracle: Optional[str]
    beaten_by: Optional[str]
    failed: Optional[str]
    budget: Optional[Reading]
    paired: Optional[Paired]
    row: Row

    @property
    def name(self) -> str:
        """``spec @ map_config``: a setting's name across map configurations."""
        return f"{self.spec} @ {self.map_config}"

    @property
    def is_budget(self) -> bool:
        """An error budget's row (judged against the frontier, never on it)."""
        return self.kind == BUDGET

    @classmethod
    def of(cls, row: Row) -> Setting:
        """Reads one frontier line.

        Args:
            row: A row of ``frontier.jsonl``.

        Returns:
            The setting.

        Raises:
            RowError: A column missing or mistyped.
        """
        kind = row.text("kind")
        budget = None
        if row.has("budget"):
            budget = Reading(row.number("budget.predicted"), row.flag("budget.target_met"), row.number("budget.search_ms"), row.integer("budget.tries"))
        paired = Paired(row.number("paired.ms"), row.number("paired.oracle_ms")) if row.has("paired") else None
        return cls(
            scene=row.text("scene"),
            spec=row.text("spec"),
            method=row.text("method"),
            map_config=row.text("map_config"),
            kind=kind,
            maps=row.integer("maps"),
            map_size=row.integer("map_size"),
            rmse=row.number("rmse"),
            frame_ms=row.number("frame_ms"),
            target=target_of(row) if kind == BUDGET else None,
            oracle=row.optional_text("oracle"),
            beaten_by=row.optional_text("beaten_by"),
            failed=row.optional_text("failed"),
            budget=budget,
            paired=paired,
            row=row,
        )


class Frontier(Sequence[Setting]):
    """Every line of one ``frontier.jsonl``, in file order.

    Attributes:
        table: The rows as read.
    """

    def __init__(self, table: Table) -> None:
        self.table = table
        self._settings = [Setting.of(r) for r in table]
        self._by_name = {s.name: s for s in self._settings if not s.is_budget}

    @overload
    def __getitem__(self, i: int) -> Setting: ...

    @overload
    def __getitem__(self, i: slice) -> Sequence[Setting]: ...

    def __getitem__(self, i: Union[int, slice]) -> Union[Setting, Sequence[Setting]]:
        return self._settings[i]

    def __len__(self) -> int:
        return len(self._settings)

    def __iter__(self) -> Iterator[Setting]:
        return iter(self._settings)

    @property
    def fixed(self) -> list[Setting]:
        """The fixed settings that were measured (not budget rows, not failed)."""
        return [s for s in self._settings if not s.is_budget and s.failed is None]

    def budget_rows(self, method: Optional[str] = None) -> list[Setting]:
        """The budget rows that were measured, in file order.

        Args:
            method: ``auto`` or ``regions`` alone; every budget row by default.

        Returns:
            The rows.
        """
        return [s for s in self._settings if s.is_budget and s.failed is None and (method is None or s.method == method)]

    def budget_row(self, method: str, target: float) -> Setting:
        """The budget row of ``method`` at T.

        Args:
            method: ``auto`` or ``regions``.
            target: T.

        Returns:
            The row.

        Raises:
            RowError: The frontier has no such row.
        """
        for s in self.budget_rows(method):
            if s.target == target:
                return s
        raise RowError(f"{self.table.path}: no {method} row at target {target}")

    def setting(self, name: Optional[str]) -> Optional[Setting]:
        """The fixed setting of that name (``spec @ map_config``), None for None.

        Args:
            name: A setting's name, as ``oracle`` and ``beaten_by`` give it.

        Returns:
            The setting.

        Raises:
            RowError: A name the frontier does not hold.
        """
        if name is None:
            return None
        if name not in self._by_name:
            raise RowError(f"{self.table.path}: names the setting {name!r}, which it does not hold")
        return self._by_name[name]

    def oracle(self, row: Setting) -> Optional[Setting]:
        """A budget row's oracle, as the lab named it.

        Args:
            row: A budget row of this frontier.

        Returns:
            The oracle, or None where no fixed setting reaches T.
        """
        return self.setting(row.oracle)

    def matched(self, row: Setting) -> Optional[Setting]:
        """The cheapest fixed setting whose RMSE is at most a budget row's own, as the lab named it.

        Args:
            row: A budget row of this frontier.

        Returns:
            The setting, or None where none is as accurate.
        """
        return self.setting(row.beaten_by)

    def same_v(self, maps: int, rmse: float) -> Optional[Setting]:
        """The fixed setting whose V is a row's: the same maps and the same RMSE, bit for bit.

        Args:
            maps: The row's maps.
            rmse: Its RMSE.

        Returns:
            The first such setting, or None where the frontier holds none.
        """
        return next((s for s in self.fixed if s.rmse == rmse and s.maps == maps), None)


def read_frontier(path: PathLike) -> Frontier:
    """Reads one ``frontier.jsonl``.

    Args:
        path: The file.

    Returns:
        Its settings.

    Raises:
        RowError: A missing file or a malformed line.
    """
    return Frontier(read(path))


@dataclass(frozen=True)
class Summary:
    """A budget row against the fixed settings of its frontier.

    Attributes:
        row: The budget row.
        matched: The cheapest fixed setting at most as wrong as the row.
        oracle: The cheapest fixed setting at most T.
        dominated: A fixed setting both as fast (strictly faster with ``strict``) and at most as wrong.
        time_over_oracle: Side by side where the row was paired, else from the two windows.
    """

    row: Setting
    matched: Optional[Setting]
    oracle: Optional[Setting]
    dominated: bool
    time_over_oracle: Optional[float]


def summarize(frontier: Frontier, strict: bool = True) -> list[Summary]:
    """Every measured budget row of a frontier against its fixed settings.

    Args:
        frontier: The frontier.
        strict: Whether ``dominated`` needs a strictly faster setting.

    Returns:
        One summary per budget row, in file order.
    """
    out = []
    for r in frontier.budget_rows():
        m, o = frontier.matched(r), frontier.oracle(r)
        dominated = m is not None and (m.frame_ms < r.frame_ms if strict else m.frame_ms <= r.frame_ms)
        if r.paired is not None:
            ratio: Optional[float] = r.paired.ms / r.paired.oracle_ms
        else:
            ratio = r.frame_ms / o.frame_ms if o is not None else None
        out.append(Summary(r, m, o, dominated, ratio))
    return out
