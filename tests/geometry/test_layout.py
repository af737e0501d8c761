"""Layouts (hex ordering and counts), kinematics conventions, presets."""

import math

import numpy as np
import pytest

from supcoord.errors import FormatError, InputError
from supcoord.geometry import AlphaBeta, Rotary, hex_count, hex_grid, layout_from_spec, points_layout
from supcoord.geometry.collision import colliding_pairs
from supcoord.geometry.presets_table import PRESETS, folded_position, preset_kinematics
from supcoord.geometry.kinematics import kinematics_from_spec
from supcoord.problems.presets import preset_problem


def _hex_distance(xy, pitch):
    """Hex (axial) distance from the centre of lattice points p·(a + b/2, b·√3/2)."""
    b = np.rint(xy[:, 1] / (pitch * math.sqrt(3) / 2)).astype(int)
    a = np.rint(xy[:, 0] / pitch - b / 2).astype(int)
    assert np.allclose(pitch * np.c_[a + b / 2, b * math.sqrt(3) / 2], xy)
    return (np.abs(a) + np.abs(b) + np.abs(a + b)) // 2


@pytest.mark.parametrize("rings", range(0, 7))
def test_hex_count_and_ordering(rings):
    pitch = 22.4
    xy = hex_grid(rings, pitch)
    assert len(xy) == hex_count(rings) == 1 + 3 * rings * (rings + 1)
    assert np.allclose(xy[0], 0)
    dist = _hex_distance(xy, pitch)
    start = 1
    for r in range(1, rings + 1):
        ring = xy[start:start + 6 * r]
        assert np.all(dist[start:start + 6 * r] == r)  # ring by ring
        assert np.allclose(ring[0], [r * pitch, 0.0])  # starts on +x
        angles = np.mod(np.arctan2(ring[:, 1], ring[:, 0]), 2 * np.pi)
        assert np.all(np.diff(angles) > 0)  # counter-clockwise
        start += 6 * r
    assert len(np.unique(xy.round(6), axis=0)) == len(xy)
    if rings:
        d = np.linalg.norm(xy[:, None] - xy[None], axis=-1) + np.eye(len(xy)) * 1e9
        assert np.allclose(d.min(axis=1), pitch)


def test_hex_ring_one_explicit():
    xy = hex_grid(1, 1.0)
    expect = [[0, 0]] + [[math.cos(math.pi / 3 * k), math.sin(math.pi / 3 * k)] for k in range(6)]
    assert np.allclose(xy, expect)


def test_layout_spec_errors():
    assert layout_from_spec({"kind": "points", "xy": [[0, 0], [1, 2]]}).shape == (2, 2)
    with pytest.raises(FormatError, match="layout.kind"):
        layout_from_spec({"kind": "square"})
    with pytest.raises(FormatError, match="layout.rings"):
        layout_from_spec({"kind": "hex", "rings": -1, "pitch": 1})
    with pytest.raises(FormatError, match="layout.pitch"):
        layout_from_spec({"kind": "hex", "rings": 1, "pitch": 0})
    with pytest.raises(FormatError, match=r"layout.xy\[1\]"):
        points_layout([[0, 0], [1]])
    with pytest.raises(InputError, match="repeats"):
        points_layout([[0, 0], [0, 0]])


def test_rotary_convention():
    kin = Rotary(10.0, 12)
    seg = kin.segments(np.array([[0], [1], [3], [6]]))
    assert np.allclose(seg[:, 0], 0)
    assert np.allclose(seg[0, 1], [10, 0])
    assert seg[1, 1, 1] < 0  # forward = clockwise
    assert np.allclose(seg[2, 1], [0, -10]) and np.allclose(seg[3, 1], [-10, 0])
    assert [q.tolist() for q in kin.neighbours([11])] == [[0], [10]]  # wraps
    assert kin.joint_distance([11], [1]).tolist() == [2]
    assert kin.signed_delta([11], [0]).tolist() == [1] and kin.signed_delta([0], [11]).tolist() == [-1]
    assert kin.reach == 10.0
    assert np.isclose(kin.sweep_length([1]), 10 * 2 * math.pi / 12)


def test_alpha_beta_convention():
    kin = AlphaBeta(7.4, 15.0, 36, 19, (0.0, 180.0))
    assert kin.n_positions == 36 * 19
    elbow, fibre = kin.segments([9, 0])  # α = 90°, β = 0
    assert np.allclose(elbow, [0, 7.4]) and np.allclose(fibre, [0, 22.4])
    elbow, fibre = kin.segments([0, 18])  # β = 180°: folded back through the base
    assert np.allclose(fibre, [7.4 - 15.0, 0])
    assert np.isclose(kin.reach, 22.4)
    # hard stops on beta, wrap on alpha
    assert kin.step([0, 18], 1, +1) is None and kin.step([0, 0], 1, -1) is None
    assert kin.step([35, 3], 0, +1).tolist() == [0, 3]
    assert len(kin.neighbours([5, 0])) == 3 and len(kin.neighbours([5, 7])) == 4
    assert kin.joint_distance([35, 0], [1, 18]).tolist() == [2, 18]
    pos = kin.all_positions()
    assert np.array_equal(kin.flat_index(pos), np.arange(len(pos)))
    moons = AlphaBeta(8.0, 17.0, 12, 12, (-180.0, 150.0))
    assert np.isclose(moons.reach, 25.0)  # β = 0 inside the range
    short = AlphaBeta(8.0, 17.0, 12, 12, (90.0, 180.0))
    assert np.isclose(short.reach, math.hypot(8, 17))


def test_steps_wrap_and_directions_are_one_rule():
    """step, step_array, wrap and directions agree: one move at a time, the short way round."""
    kin = AlphaBeta(7.4, 15.0, 6, 4)
    pos = kin.all_positions()
    for joint, delta in kin.moves():
        nxt, ok = kin.step_array(pos, joint, delta)
        for q, n, o in zip(pos, nxt, ok):
            s = kin.step(q, joint, delta)
            assert (s is None) == (not o) and (s is None or s.tolist() == n.tolist())
        assert np.array_equal(ok, kin.step_valid(pos, joint, delta))
    assert kin.wrap([[6, 2], [-1, 3]]).tolist() == [[0, 2], [5, 3]]  # alpha wraps, beta does not
    assert kin.directions([0, 0], [0, 0]) == [(), ()]
    assert kin.directions([0, 0], [3, 2]) == [(+1, -1), (+1,)]  # half a turn: both ways
    assert kin.directions([0, 3], [5, 1]) == [(-1,), (-1,)]
    rot = Rotary(10.0, 2)
    assert rot.directions([0], [1]) == [(+1, -1)] and rot.signed_delta([1], [0]).tolist() == [1]


def test_kinematics_spec_errors():
    with pytest.raises(FormatError, match="kinematics.kind"):
        kinematics_from_spec({"kind": "delta"})
    with pytest.raises(InputError, match="kinematics.steps"):
        kinematics_from_spec({"kind": "rotary", "arm": 1.0, "steps": 1})
    with pytest.raises(FormatError, match="kinematics.beta_steps is missing"):
        kinematics_from_spec({"kind": "alpha-beta", "alpha": 1, "beta": 2, "alpha_steps": 4})
    with pytest.raises(InputError, match="beta_range"):
        kinematics_from_spec({"kind": "alpha-beta", "alpha": 1, "beta": 2, "alpha_steps": 4, "beta_steps": 3,
                              "beta_range": [10, 5]})
    with pytest.raises(InputError, match="kinematics.arm"):
        kinematics_from_spec({"kind": "rotary", "arm": True, "steps": 4})


def test_presets_match_references():
    s = PRESETS["sdss-v"]
    assert (s.pitch, s.alpha, s.beta, s.buffer) == (22.4, 7.4, 15.0, 2.0)
    d = PRESETS["desi"]
    assert (d.pitch, d.alpha, d.beta) == (10.4, 3.0, 3.0)
    m = PRESETS["moons"]
    assert (m.pitch, m.alpha, m.beta, m.beta_range) == (None, 8.0, 17.0, (-180.0, 150.0))
    p = PRESETS["pfs"]
    assert (p.pitch, p.alpha, p.beta) == (8.0, 2.4, 2.4)
    with pytest.raises(InputError, match="pitch"):
        preset_problem("moons", rings=1)
    with pytest.raises(InputError, match="unknown preset"):
        preset_kinematics("hectospec")


def test_sdss_folded_lattice_is_collision_free():
    kin = preset_kinematics("sdss-v")
    q = folded_position(kin)
    assert q == (1, 17)
    bases = hex_grid(3, 22.4)
    assert colliding_pairs(kin, bases, 2.0, np.tile(q, (len(bases), 1))) == []
    prob = preset_problem("sdss-v", rings=2, seed=5, start="folded", near=3)
    assert np.all(prob.start == q)
    assert np.all(kin.joint_distance(prob.start, prob.target) <= 3)
