"""The exact least distance of a segment turning about a fixed centre past a static segment.

A single move turns the colliding segment rigidly about a fixed centre ``c`` (rotary:
the base; alpha joint: the base; beta joint: the elbow) by ``φ = Δ·t``, ``t ∈ [0, 1]``:
``A(t) = c + e^{iΔt}·(A(0) − c)`` against a static segment ``B``.  Where the segments do
not meet, ``d(t)`` is the least of four point–segment distances: an end ``P`` of ``A``
(on a circle about ``c``) against ``B``, or an end ``Q`` of ``B`` against ``A(t)`` (in
``A``'s frame, ``Q`` turns by ``−Δt`` on a circle about ``c``).  The least distance from
a point turning on a circle of radius ``ρ`` about ``c`` to a fixed segment ``S``, over an
arc, is attained at one of (stationarity of ``|P − X|`` with ``P − X`` radial, or zero):

- the ends of the arc;
- the point of the circle in the direction of an end of ``S`` (``X`` an end of ``S``);
- the points of the circle in the directions ``±n`` of ``S``'s normal (``X`` inside ``S``);
- the points where the circle crosses ``S`` (distance 0).

If the segments meet at some ``t``, they do so at ``t = 0`` or first where an end of one
touches the other (a proper crossing persists under small motions), which is one of
the points above.  So ``min_t d(t)`` is the least of ``d`` at these **critical times**
(at most 26 per motion), each evaluated with the arm's own formula at ``q + t·δ``
(:meth:`.oracle_model.Arm.segment`), so that ``t = 0`` and ``t = 1`` give exactly the static
distances.  This decides the ties the branch and bound of :mod:`.certified_sweep` cannot: a
motion whose least distance is *exactly* ``r`` — a flat stretch (an arm turning about
its own base, at ``r`` from a static point) or a tangency at a grid position — is free.

>>> import numpy as np
>>> t = critical_times(np.array([0j]), np.array([-np.pi / 2]), np.array([0j]), np.array([10 + 0j]),
...                    np.array([5 - 5j]), np.array([15 - 5j]))          # a quarter turn clockwise
>>> sorted(set(np.round(t[0], 4).tolist()))[:4]
[0.0, 0.2048, 0.3333, 0.5]
"""

from __future__ import annotations

import numpy as np

__all__ = ["critical_times"]

_TAU = 2 * np.pi


def _normal(s0: np.ndarray, s1: np.ndarray) -> np.ndarray:
    d = s1 - s0
    n = np.abs(d)
    return np.where(n > 0, 1j * d / np.where(n > 0, n, 1.0), 1.0 + 0j)


def _circle_hits(c: np.ndarray, rho: np.ndarray, s0: np.ndarray, s1: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Points where the circle ``|x − c| = ρ`` crosses ``[s0, s1]``, as (point, exists)."""
    d, e = s1 - s0, s0 - c
    a = d.real**2 + d.imag**2
    b = e.real * d.real + e.imag * d.imag
    cc = e.real**2 + e.imag**2 - rho**2
    disc = b * b - a * cc
    root = np.sqrt(np.maximum(disc, 0.0))
    safe = np.where(a > 0, a, 1.0)
    out = []
    for sign in (-1.0, 1.0):
        u = (-b + sign * root) / safe
        ok = (a > 0) & (disc >= 0) & (u >= 0) & (u <= 1)
        out.append((s0 + np.clip(u, 0, 1) * d, ok))
    return out


def _targets(c: np.ndarray, rho: np.ndarray, s0: np.ndarray, s1: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Directions (from ``c``) of the critical points of a circle of radius ``ρ`` against ``[s0, s1]``."""
    n = _normal(s0, s1)
    always = np.ones(np.shape(c), dtype=bool)
    out = [(np.angle(s0 - c), always), (np.angle(s1 - c), always), (np.angle(n), always), (np.angle(-n), always)]
    out += [(np.angle(x - c), ok) for x, ok in _circle_hits(c, rho, s0, s1)]
    return out


def _to_time(phi: np.ndarray, delta: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """The ``t ∈ [0, 1]`` with ``Δ·t ≡ φ (mod 2π)``, or 0 where there is none (``|Δ| < 2π``)."""
    turn = np.where(delta >= 0, np.mod(phi, _TAU), np.mod(-phi, _TAU))
    mag = np.abs(delta)
    t = turn / np.where(mag > 0, mag, 1.0)
    return np.where(ok & (mag > 0) & (t <= 1.0), t, 0.0)


def critical_times(c: np.ndarray, delta: np.ndarray, a0: np.ndarray, a1: np.ndarray, b0: np.ndarray,
                   b1: np.ndarray) -> np.ndarray:
    """``(E, 26)`` times in ``[0, 1]`` among which ``d(t)`` takes its least value (module
    docstring): the segment ``[a0, a1]`` (at ``t = 0``) turning by ``delta·t`` about ``c``
    past the static ``[b0, b1]`` (complex arrays over entries ``E``)."""
    times = [np.zeros(np.shape(c)), np.ones(np.shape(c))]
    for p in (a0, a1):  # an end of the moving segment against the static one
        v = p - c
        for phi, ok in _targets(c, np.abs(v), b0, b1):
            times.append(_to_time(phi - np.angle(v), delta, ok))
    for q in (b0, b1):  # an end of the static segment against the moving one, in its frame
        w = q - c
        for phi, ok in _targets(c, np.abs(w), a0, a1):
            times.append(_to_time(np.angle(w) - phi, delta, ok))
    return np.stack(times, axis=-1)
