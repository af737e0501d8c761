"""The cheap verdicts of a turning segment (:func:`supcoord.geometry.sweep.rotation_certain`):
complete where the bisection bound promises, sound at the margin, and the same entry by
entry whatever the shapes the arguments are broadcast from.

The reference is the closed-form clearance (:func:`rotation_clearance`, itself checked
against dense sampling in ``test_sweep.py``) and, for the annulus, the testing oracle's own
segment distance (:mod:`supcoord.testing.oracle.distance`).  These checks were written for
mutants of ``sweep.py`` that the soundness tests alone let through (mutation testing:
``benchmarks/mutation_run.py geometry``).
"""

from __future__ import annotations

import numpy as np
import pytest

from supcoord.geometry.sweep import MARGIN, rotation_certain, rotation_clearance, turn_radii, turn_slack


def test_turn_slack_is_the_chord_of_half_a_piece():
    rng = np.random.default_rng(1)
    r, angle = rng.uniform(0, 20, 200), rng.uniform(-2 * np.pi, 2 * np.pi, 200)
    assert np.allclose(turn_slack(r, angle), _chord(r, angle), rtol=1e-12, atol=1e-12)
    for parts in (2, 4, 8):
        assert np.allclose(turn_slack(r, angle, parts), _chord(r, angle, parts), rtol=1e-12, atol=1e-12)
from supcoord.testing.oracle.distance import segment_gap


def _chord(r, angle, parts=1):
    """How far a point at radius ``r`` moves in a turn by ``|angle| / (2·parts)``: the distance
    between it and its turned self (the farthest a pose of a piece ``|angle| / parts`` can be
    from the piece's nearer end)."""
    x = np.asarray(r, float) + 0j
    return np.abs(x * np.exp(1j * np.abs(np.asarray(angle, float)) / (2 * parts)) - x)


def _turns(seed: int, n: int):
    """``n`` random turns: segments, centres (a third at the segment's first end, as beta
    turns), angles up to ±π, standing segments near, around or far from the centre, buffers."""
    rng = np.random.default_rng(seed)
    seg, other = rng.uniform(-6, 6, (n, 2, 2)), rng.uniform(-6, 6, (n, 2, 2))
    centre = np.where((np.arange(n) % 3 == 0)[:, None], seg[:, 0], rng.uniform(-4, 4, (n, 2)))
    scale = rng.choice([0.05, 1.0, 3.0], n)[:, None, None]
    other = centre[:, None] + scale * (other - centre[:, None])
    angle = rng.uniform(-1, 1, n) * rng.choice([0.1, 0.6, np.pi], n)
    bsum = rng.uniform(0.0, 3.0, n)
    return seg, centre, angle, other, bsum


@pytest.mark.parametrize("depth", [0, 1, 2, 3])
def test_every_turn_clear_by_the_bisection_slack_is_called_free(depth):
    """A piece of the turn is clear when the mean clearance at its ends, less
    ``turn_slack(r_max, Δ, 2**depth)``, keeps ``bsum + MARGIN``; the ends' clearance is at
    least the whole turn's, so a turn whose exact clearance keeps that much is free."""
    seg, centre, angle, other, bsum = _turns(21, 4000)
    exact = rotation_clearance(seg, centre, angle, other)
    _, r_max = turn_radii(seg, centre)
    surely = exact >= bsum + 2 * MARGIN + _chord(r_max, angle, 2 ** depth)
    free, hit = rotation_certain(seg, centre, angle, other, bsum, depth=depth)
    assert surely.sum() > 500  # the property is exercised
    assert np.all(free[surely]) and not np.any(hit[surely])


def test_a_standing_segment_beyond_the_annulus_is_free_at_any_depth():
    """Half turns past segments farther from the centre than ``r_max + bsum`` (the oracle's
    distance): free, however little the bisection decides."""
    rng = np.random.default_rng(5)
    n = 500
    seg = rng.uniform(-2, 2, (n, 2, 2))
    centre = np.zeros((n, 2))
    _, r_max = turn_radii(seg, centre)
    bsum = rng.uniform(0.1, 1.0, n)
    a = rng.uniform(0, 2 * np.pi, n)
    d = r_max + bsum + rng.uniform(0.01, 0.5, n)  # the nearest point of the standing segment
    mid = d * np.exp(1j * a)
    half = rng.uniform(0.1, 2.0, n) * 1j * np.exp(1j * a)  # along the tangent
    q0, q1 = mid - half, mid + half
    assert np.all(segment_gap(0, 0, q0, q1) >= r_max + bsum)  # oracle: beyond the annulus
    other = np.stack([np.stack([q0.real, q0.imag], -1), np.stack([q1.real, q1.imag], -1)], axis=1)
    angle = np.full(n, np.pi)
    for depth in (0, 2):
        free, hit = rotation_certain(seg, centre, angle, other, bsum, depth=depth)
        assert np.all(free) and not np.any(hit)


def test_a_standing_segment_inside_the_buffer_by_half_the_margin_is_not_free():
    """An arm from the centre turning half a turn past a segment tangent to the circle of its
    tip at ``r_max + bsum − MARGIN/2``: the tip comes nearer than ``bsum``, so the turn is not
    free, even though the annulus test is within its margin of calling it clear."""
    bsum = 0.5
    seg = np.array([[0.0, 0.0], [2.0, 0.0]])
    y = 2.0 + bsum - MARGIN / 2
    other = np.array([[-1.0, y], [1.0, y]])
    assert float(segment_gap(0j, 2j, -1 + 1j * y, 1 + 1j * y)) < bsum  # the tip at a quarter turn
    assert float(rotation_clearance(seg, [0.0, 0.0], np.pi, other)) < bsum
    for depth in (0, 1, 2):
        free, _ = rotation_certain(seg, [0.0, 0.0], np.pi, other, bsum, depth=depth)
        assert not bool(free), depth


def test_a_turn_that_starts_within_the_margin_and_moves_away_is_not_a_hit():
    """``hit`` means a pose certainly nearer than ``bsum``: a start pose ``bsum + MARGIN/2``
    away that only moves off is not one (its exact clearance is at least ``bsum``)."""
    bsum = 0.5
    gap = bsum + MARGIN / 2
    seg = np.array([[1.0, 0.0], [3.0, 0.0]])
    other = np.array([[1.0, -gap], [3.0, -gap]])  # below the segment, parallel
    angle = 0.3  # counter-clockwise: the segment lifts away from ``other``
    exact = float(rotation_clearance(seg, [0.0, 0.0], angle, other))
    assert exact >= bsum
    free, hit = rotation_certain(seg, [0.0, 0.0], angle, other, bsum)
    assert not bool(hit)


@pytest.mark.parametrize("which", ["seg", "centre", "angle", "other", "bsum"])
def test_each_argument_broadcasts_entry_by_entry(which):
    """Any one argument with a leading shape of its own (the others shared): the verdicts have
    that shape, and each entry is the verdict of its own scalar call."""
    seg, centre, angle, other, bsum = _turns(8, 6)
    args = {"seg": seg[0], "centre": centre[0], "angle": angle[0], "other": other[0], "bsum": bsum[0]}
    many = {"seg": seg, "centre": centre, "angle": angle, "other": other, "bsum": bsum}[which]
    # a (2, 3) leading shape, so flat and shaped results differ
    trail = {"seg": (2, 2), "centre": (2,), "angle": (), "other": (2, 2), "bsum": ()}[which]
    call = dict(args, **{which: many.reshape((2, 3) + trail)})
    free, hit = rotation_certain(call["seg"], call["centre"], call["angle"], call["other"], call["bsum"])
    assert free.shape == hit.shape == (2, 3)
    for k in range(6):
        one = dict(args, **{which: many[k]})
        f1, h1 = rotation_certain(one["seg"], one["centre"], one["angle"], one["other"], one["bsum"])
        assert (bool(free.flat[k]), bool(hit.flat[k])) == (bool(f1), bool(h1)), (which, k)


def test_the_default_bisection_depth_is_two():
    seg, centre, angle, other, bsum = _turns(3, 3000)
    default = rotation_certain(seg, centre, angle, other, bsum)
    two = rotation_certain(seg, centre, angle, other, bsum, depth=2)
    three = rotation_certain(seg, centre, angle, other, bsum, depth=3)
    assert np.array_equal(default[0], two[0]) and np.array_equal(default[1], two[1])
    assert not np.array_equal(default[0], three[0])  # the depth matters on these turns


def test_bisect_turns_keeps_open_every_piece_within_the_margin():
    """The rule of :func:`bisect_turns`: a piece is clear only when the mean end clearance less
    the slack keeps ``bsum + MARGIN``; a turn whose single piece falls short of that by half
    the margin stays open, one that keeps twice the margin is decided free."""
    from supcoord.geometry.sweep import bisect_turns

    bsum, slack = np.array([0.5, 0.5]), np.array([[0.25], [0.25]])
    d = bsum + slack[:, 0] + np.array([MARGIN / 2, 2 * MARGIN])
    hit, open_ = bisect_turns(d, d, slack, bsum, lambda e, k: np.full(len(e), np.inf), 0)
    assert open_.tolist() == [True, False] and not hit.any()
    # one bisection: the middle pose nearer than bsum − MARGIN is a hit
    hit, open_ = bisect_turns(d, d, np.array([[0.25, 0.1], [0.25, 0.1]]), bsum,
                              lambda e, k: np.full(len(e), 0.2), 1)
    assert hit.tolist() == [True, False] and not open_.any()
