"""Fitted growth of a measured quantity ``y`` against a size ``x`` (positioners, family size).

Two models are fitted by least squares on ``log10 y``:

- **exponential**: ``log10 y = a + b·x``, i.e. ``y`` is multiplied by ``10^b`` per unit of
  ``x`` (per positioner): the growth of explicit state sets and of monolithic routes;
- **power**: ``log10 y = a + k·log10 x``, i.e. ``y ∝ x^k``: ``k = 1`` is linear growth.

The power model is reported unless the exponential one leaves less than half its residual
sum of squares (over a few sizes both fit slow growth about equally, and ``∝ N^1.1``
says more than ``×1.004 per positioner``); at least three distinct sizes are needed, and
the power model needs ``x > 0``.  ``r2`` is its coefficient of
determination on ``log10 y``.

>>> g = fit_growth([1, 2, 3, 4, 5], [3, 9, 27, 81, 243])
>>> g.model, round(g.rate, 3), g.label("positioner")
('exponential', 3.0, '×3 per positioner')
>>> fit_growth([10, 100, 1000], [2, 20, 200]).label("positioner")
'∝ N^1.00'
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

__all__ = ["Growth", "fit_growth"]


@dataclass(frozen=True)
class Growth:
    """A fitted growth: ``model`` (``exponential`` or ``power``), ``rate`` (the factor per
    unit of x, or the exponent), ``r2`` and the number of sizes ``points``."""

    model: str
    rate: float
    r2: float
    points: int

    def label(self, unit: str = "positioner") -> str:
        if self.model == "exponential":
            return f"×{self.rate:.3g} per {unit}" if abs(self.rate - 1) > 0.01 else f"×{self.rate:.4f} per {unit}"
        return f"∝ {'N' if unit == 'positioner' else 'size'}^{self.rate:.2f}"


def _line(xs: Sequence[float], ys: Sequence[float]) -> tuple[float, float, float]:
    """Least-squares slope, intercept and residual sum of squares."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx else 0.0
    intercept = my - slope * mx
    return slope, intercept, sum((y - intercept - slope * x) ** 2 for x, y in zip(xs, ys))


def fit_growth(xs: Sequence[float], ys: Sequence[float]) -> Growth | None:
    """The better of the two fits of ``ys`` against ``xs`` (None: fewer than three usable sizes)."""
    pairs = sorted((float(x), float(y)) for x, y in zip(xs, ys) if x is not None and y is not None and y > 0)
    if len({x for x, _ in pairs}) < 3:
        return None
    lx = [x for x, _ in pairs]
    ly = [math.log10(y) for _, y in pairs]
    my = sum(ly) / len(ly)
    total = sum((y - my) ** 2 for y in ly) or 1e-300
    b, _, rss_exp = _line(lx, ly)
    best = Growth("exponential", 10**b, 1 - rss_exp / total, len(set(lx)))
    if all(x > 0 for x in lx):
        k, _, rss_pow = _line([math.log10(x) for x in lx], ly)
        if rss_exp >= 0.5 * rss_pow:
            best = Growth("power", k, 1 - rss_pow / total, len(set(lx)))
    return best
