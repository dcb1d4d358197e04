"""auto's per-frame record (run.json's ``method_record``), read through one type.

The engine writes it from ``AutoRecord`` (src/methods/auto/record.rs), tagged
``"method": "auto"`` (records written before the tag lack it and are read as auto's); this is
its one reader in Python. A record that is not auto's, or lacks a field, is a ``ValueError``
naming the file and the field.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Optional

__all__ = ["AutoRecord", "AutoTry"]


@dataclass(frozen=True)
class AutoTry:
    """One try of a frame's search: the centred grid, its maps, its wall clock and prediction."""

    n: int
    map_size: int
    maps: int
    ms: float
    predicted_rmse: float


@dataclass(frozen=True)
class AutoRecord:
    """One frame of ``auto``: the grid chosen, the target and whether it was met, the tries,
    what it renders, the certified decision where there was one, and the out-of-reach warning."""

    chosen_spec: str
    chosen_map_size: int
    target: float
    target_met: bool
    tries: tuple[AutoTry, ...]
    predicted_rmse: float
    renders: Optional[str]
    filter_chosen: Optional[str]
    certified_bound: Optional[float]
    certified_ms: float
    warning: Optional[str]

    @classmethod
    def read(cls, record: Mapping[str, Any], where: str = "run.json") -> "AutoRecord":
        """Reads ``record`` (a run.json's ``method_record``).

        Args:
            record: the record as parsed from JSON.
            where: the file it came from, for the message.

        Returns:
            The typed record.

        Raises:
            ValueError: it is another method's record, or a field is missing or of the wrong type.
        """
        def need(obj: Any, key: str, path: str) -> Any:
            if not isinstance(obj, Mapping) or key not in obj:
                raise ValueError(f"{where}: method_record.{path}{key} is missing: not an auto record?")
            return obj[key]

        method = record.get("method", "auto") if isinstance(record, Mapping) else None
        if method != "auto":
            raise ValueError(f"{where}: method_record.method = {method!r}: not an auto record")
        try:
            chosen = need(record, "chosen", "")
            tries = tuple(
                AutoTry(int(need(t, "n", "tries[].")), int(need(t, "map_size", "tries[].")), int(need(t, "maps", "tries[].")),
                        float(need(t, "ms", "tries[].")), float(need(t, "predicted_rmse", "tries[].")))
                for t in need(record, "tries", "")
            )
            certified = record.get("certified")
            flt = record.get("filter")
            return cls(
                chosen_spec=str(need(chosen, "spec", "chosen.")),
                chosen_map_size=int(need(chosen, "map_size", "chosen.")),
                target=float(need(record, "target", "")),
                target_met=bool(need(record, "target_met", "")),
                tries=tries,
                predicted_rmse=float(need(record, "predicted_rmse", "")),
                renders=record.get("renders"),
                filter_chosen=flt.get("chosen") if isinstance(flt, Mapping) else None,
                certified_bound=float(need(certified, "bound", "certified.")) if certified else None,
                certified_ms=float(need(certified, "decision_ms", "certified.")) if certified else 0.0,
                warning=record.get("warning"),
            )
        except (TypeError, ValueError) as e:
            if str(e).startswith(where):
                raise
            raise ValueError(f"{where}: method_record: {e}") from e

    def choice(self) -> str:
        """What the frame rendered: the filter's name, else ``spec @ map_size`` of the grid."""
        return self.renders or self.filter_chosen or f"{self.chosen_spec} @ {self.chosen_map_size}"

    def reported(self) -> float:
        """The figure set against the target: the certified bound where it decided, else the
        prediction."""
        return self.certified_bound if self.certified_bound is not None else self.predicted_rmse

    def search_ms(self) -> float:
        """The wall clock of the decision: every try's, and the certified decision's, ms."""
        return sum(t.ms for t in self.tries) + self.certified_ms
