"""The analysis behind the figures in ``results/``: every figure a results folder publishes is
computed here, tested by ``python/tests/``, and driven by the folder's short driver.

- :mod:`~penumbra.analysis.rows`: one reader for every rows file (CSV or JSON Lines), columns by
  name and typed on read, errors naming file, line and column; the build from the rows' own
  ``version``.
- :mod:`~penumbra.analysis.engine`: what the analyses need of the engine and the lab, read from
  them: the calibration's factors, the promise, a spec's parameters, ``auto``'s and ``regions``'
  laws.
- :mod:`~penumbra.analysis.frontier`: a frontier's rows, and the oracle as the lab names it.
- :mod:`~penumbra.analysis.promise`: ``auto``'s rows counted against its promise.
- :mod:`~penumbra.analysis.retake`: ``auto``'s rows rendered again beside their oracles.
- :mod:`~penumbra.analysis.auto_record`: ``auto``'s per-frame record, read through one type.
- :mod:`~penumbra.analysis.calibration`: the calibrated estimate's pairs.
- :mod:`~penumbra.analysis.budget`: the error budget's prices, stretches and reference.
- :mod:`~penumbra.analysis.regions`: the per-region method's rows.
- :mod:`~penumbra.analysis.binary`: running the ``penumbra`` binary for a driver's renders.
- :mod:`~penumbra.analysis.stats`: medians, quantiles, rank correlation, coverage on a grid.

docs/python.md ("Analysis of results") is the guide.
"""

from .rows import Row, RowError, Table, build_line, read, read_json, write_csv, write_csv_file

__all__ = ["Row", "RowError", "Table", "build_line", "read", "read_json", "write_csv", "write_csv_file"]
