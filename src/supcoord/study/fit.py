"""Fitted growth of a measured quantity ``y`` against a size ``x`` (positioners, family size).

Three two-parameter models are fitted to every size of a series:

- **power**: ``log10 y = a + k·log10 x``, i.e. ``y ∝ x^k`` (``k = 1``: proportional);
- **linear**: ``y = a + b·x`` by least squares on ``y``: a fixed cost plus a cost per unit of
  ``x``, as the memory of a process (the interpreter's tens of MB, then a little per
  positioner);
- **exponential**: ``log10 y = a + b·x``, i.e. ``y`` is multiplied by ``10^b`` per unit of
  ``x``: the growth of explicit state sets and of monolithic routes.

**The criterion.** Each model is scored by its residual sum of squares on ``log10 y`` (the
relative error, the same scale for all three; a linear fit that predicts ``y ≤ 0`` somewhere
is out).  The power law is kept unless another model leaves less than half its residual;
then the linear one is kept unless the exponential leaves less than half of *its*
residual.  So the simplest reading wins when the data cannot tell them apart (over a few
sizes ``∝ N^1.1`` says more than ``×1.004 per positioner``).

The fit uses every size of the series (not only its largest), so it describes the curve it
labels: a rising series gets a rising fit, a falling one a falling fit.  At least three distinct sizes are needed, and the power model needs ``x > 0``.
``r2`` is the chosen model's coefficient of determination on ``log10 y``.

:func:`series_growth` is the one place a study's fits are computed: the legends of
:mod:`.plots` and any table of fits (notebooks, reports) call it.

>>> g = fit_growth([1, 2, 3, 4, 5], [3, 9, 27, 81, 243])
>>> g.model, round(g.rate, 3), g.label("positioner")
('exponential', 3.0, '×3 per positioner')
>>> fit_growth([10, 100, 1000], [2, 20, 200]).label("positioner")
'∝ N^1.00'
>>> fit_growth([10, 100, 1000, 3000], [65, 66, 75, 95]).label("positioner")
'linear, +0.01 per positioner'
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["Growth", "fit_growth", "series_growth", "series_medians"]

#: residual (``log10`` units squared, per point) below which a fit counts as exact: two exact
#: fits of one series differ only by rounding, and the simpler one is kept
RSS_FLOOR = 1e-20


@dataclass(frozen=True)
class Growth:
    """A fitted growth.

    Attributes
    ----------
    model : str
        ``"power"``, ``"linear"`` or ``"exponential"`` (module docstring).
    rate : float
        The exponent ``k`` (power), the increase per unit of x ``b`` in y's unit
        (linear), or the factor per unit of x ``10^b`` (exponential).
    r2 : float
        Coefficient of determination on ``log10 y``.
    points : int
        Number of distinct sizes fitted.
    """

    model: str
    rate: float
    r2: float
    points: int

    def label(self, unit: str = "positioner") -> str:
        """The legend text: ``∝ N^1.50``, ``linear, +0.19 per positioner``, ``×2 per positioner``."""
        if self.model == "exponential":
            return f"×{self.rate:.3g} per {unit}" if abs(self.rate - 1) > 0.01 else f"×{self.rate:.4f} per {unit}"
        if self.model == "linear":
            return f"linear, {self.rate:+.2g} per {unit}"
        return f"∝ {'N' if unit == 'positioner' else 'size'}^{self.rate:.2f}"


def _line(xs: Sequence[float], ys: Sequence[float]) -> tuple[float, float]:
    """Least-squares slope and intercept."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx else 0.0
    return slope, my - slope * mx


def _rss(ly: Sequence[float], predicted: Iterable[float]) -> float:
    return sum((a - b) ** 2 for a, b in zip(ly, predicted))


def _usable(xs: Sequence[float], ys: Sequence[float]) -> list[tuple[float, float]]:
    """The ``(x, y)`` pairs with finite numbers and ``y > 0``, in increasing order."""
    def finite(v: Any) -> bool:
        return v is not None and math.isfinite(float(v))

    return sorted((float(x), float(y)) for x, y in zip(xs, ys) if finite(x) and finite(y) and y > 0)


def _fits(lx: list[float], y: list[float], ly: list[float]) -> dict[str, tuple[float, float]]:
    """Each model that can fit: model -> (rate, residual sum of squares on ``log10 y``)."""
    fits: dict[str, tuple[float, float]] = {}
    b, a = _line(lx, ly)
    fits["exponential"] = (10**b, _rss(ly, (a + b * x for x in lx)))
    slope, icpt = _line(lx, y)
    if all(icpt + slope * x > 0 for x in lx):
        fits["linear"] = (slope, _rss(ly, (math.log10(icpt + slope * x) for x in lx)))
    if all(x > 0 for x in lx):
        k, a = _line([math.log10(x) for x in lx], ly)
        fits["power"] = (k, _rss(ly, (a + k * math.log10(x) for x in lx)))
    return fits


def fit_growth(xs: Sequence[float], ys: Sequence[float]) -> Growth | None:
    """The model that fits ``ys`` against ``xs`` best by the module's criterion.

    Parameters
    ----------
    xs : sequence of float
        Sizes (positioners or a family's parameter); pairs with ``y ≤ 0`` or ``None`` are left out.
    ys : sequence of float
        The measured values (seconds, MB, nodes), one per size (a median over seeds).

    Returns
    -------
    Growth or None
        None with fewer than three distinct usable sizes.
    """
    pairs = _usable(xs, ys)
    points = len({x for x, _ in pairs})
    if points < 3:
        return None
    lx = [x for x, _ in pairs]
    ly = [math.log10(y) for _, y in pairs]
    my = sum(ly) / len(ly)
    total = sum((y - my) ** 2 for y in ly) or 1e-300
    fits = _fits(lx, [y for _, y in pairs], ly)
    order = [m for m in ("power", "linear", "exponential") if m in fits]
    best = order[0]
    for model in order[1:]:  # a residual within rounding of zero is no better than another such
        if fits[model][1] < 0.5 * fits[best][1] and fits[best][1] > RSS_FLOOR * len(lx):
            best = model
    rate, rss = fits[best]
    return Growth(best, rate, 1 - rss / total, points)


def series_medians(rows: Iterable[Mapping[str, Any]], metric: str) -> dict[str, tuple[list[int], list[float]]]:
    """Per series, its sizes in increasing order and the median of ``metric`` over the
    finished (``status == "ok"``) cases at each size: what the figures draw and fit."""
    by: dict[str, dict[int, list[float]]] = {}
    for r in rows:
        x = r.get("positioners") if r.get("positioners") is not None else r.get("size")
        if r.get("status") == "ok" and r.get(metric) is not None and x is not None:
            by.setdefault(r["series"], {}).setdefault(x, []).append(float(r[metric]))
    return {name: (sorted(v), [statistics.median(v[x]) for x in sorted(v)]) for name, v in sorted(by.items())}


def series_growth(rows: Iterable[Mapping[str, Any]], metric: str) -> dict[str, Growth | None]:
    """The fitted growth of each series' median ``metric`` over all its sizes (rows as
    :func:`~supcoord.study.results.results_rows` returns them); the one fit that the
    figures' legends and any table of a study's growth show.

    >>> rows = [{"series": "s", "status": "ok", "positioners": n, "seconds": 0.1 * n ** 1.5} for n in (10, 20, 40, 80)]
    >>> series_growth(rows, "seconds")["s"].label()
    '∝ N^1.50'
    """
    return {name: fit_growth(xs, med) for name, (xs, med) in series_medians(rows, metric).items()}
