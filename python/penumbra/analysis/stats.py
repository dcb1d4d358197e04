"""The few statistics the results' analyses share: medians and quantiles, rank correlation, and
the least value on a grid that covers a share of rows."""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Sequence
from typing import Callable, Optional, TypeVar

T = TypeVar("T")


def median(xs: Iterable[float]) -> float:
    """The median (the mean of the middle two for an even count).

    Args:
        xs: The values; at least one.

    Returns:
        The median.

    Raises:
        ValueError: No values.
    """
    values = list(xs)
    if not values:
        raise ValueError("the median of no values")
    return statistics.median(values)


def quantile(xs: Iterable[float], p: float) -> float:
    """The p-quantile with linear interpolation between order statistics (numpy's default).

    Args:
        xs: The values; at least one.
        p: The share, 0 to 1.

    Returns:
        The quantile.

    Raises:
        ValueError: No values, or p outside [0, 1].
    """
    values = sorted(xs)
    if not values:
        raise ValueError("the quantile of no values")
    if not 0.0 <= p <= 1.0:
        raise ValueError(f"quantile share {p} outside [0, 1]")
    k = (len(values) - 1) * p
    i = int(k)
    return values[i] + (values[min(i + 1, len(values) - 1)] - values[i]) * (k - i)


def ranks(xs: Sequence[float]) -> list[int]:
    """Each value's rank, 0 for the smallest; ties ranked in the order they come.

    Args:
        xs: The values.

    Returns:
        One rank per value.
    """
    order = sorted(range(len(xs)), key=lambda i: xs[i])
    r = [0] * len(xs)
    for k, i in enumerate(order):
        r[i] = k
    return r


def pearson(xs: Sequence[float], ys: Sequence[float]) -> float:
    """Pearson's correlation coefficient.

    Args:
        xs: The first values.
        ys: The second, as many.

    Returns:
        The coefficient, -1 to 1.

    Raises:
        ValueError: Fewer than two pairs, unequal lengths, or a constant series.
    """
    if len(xs) != len(ys) or len(xs) < 2:
        raise ValueError(f"correlation of {len(xs)} and {len(ys)} values")
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    sxx = sum((x - mx) ** 2 for x in xs)
    syy = sum((y - my) ** 2 for y in ys)
    if sxx == 0 or syy == 0:
        raise ValueError("correlation of a constant series")
    return sxy / math.sqrt(sxx * syy)


def spearman(xs: Sequence[float], ys: Sequence[float]) -> float:
    """Spearman's rho: Pearson's correlation of the ranks (ties in the order they come).

    Args:
        xs: The first values.
        ys: The second, as many.

    Returns:
        Rho, -1 to 1.
    """
    return pearson([float(r) for r in ranks(xs)], [float(r) for r in ranks(ys)])


def share(items: Sequence[T], keep: Callable[[T], bool]) -> float:
    """The share of items ``keep`` accepts (0 for none).

    Args:
        items: The items.
        keep: The test.

    Returns:
        A share, 0 to 1.
    """
    return sum(1 for x in items if keep(x)) / len(items) if items else 0.0


def least_covering(grid: Iterable[float], items: Sequence[T], covers: Callable[[T, float], bool], percent: float) -> Optional[float]:
    """The first value of ``grid`` at which ``covers`` holds on at least ``percent`` % of the
    items (counted in whole items, so 95 % of 42 is 40).

    Args:
        grid: Candidate values, in the order to try them (usually ascending).
        items: The rows to cover.
        covers: Whether an item is covered at a value.
        percent: The share asked for, in percent.

    Returns:
        The value, or None where no value of the grid covers enough.
    """
    for k in grid:
        if 100 * sum(1 for x in items if covers(x, k)) >= percent * len(items):
            return k
    return None

