"""Problems of next-generation size: limits set by memory, the presets, fast and unchanged generation."""

from __future__ import annotations

import time

import numpy as np
import pytest

from supcoord.errors import FormatError, InputError
from supcoord.geometry import layout_limits
from supcoord.geometry.collision import placed_segments, segment_distance
from supcoord.geometry.kinematics import AlphaBeta
from supcoord.geometry.layout import hex_count, hex_grid, layout_from_spec
from supcoord.geometry.layout_limits import BYTES_PER_ROBOT, check_robot_count, robot_limit
from supcoord.geometry.pairs import neighbour_pairs
from supcoord.geometry.presets_table import PRESETS
from supcoord.problems.presets import preset_problem
from supcoord.problems.problem import parse_problem
from supcoord.problems.random import random_configuration

GIB = 2**30


@pytest.fixture
def memory_16gib(monkeypatch):
    monkeypatch.setattr(layout_limits, "memory_limit", lambda: 16 * GIB)


def test_104_rings_fit_in_16_gib(memory_16gib):
    assert robot_limit() == 16 * GIB // BYTES_PER_ROBOT >= hex_count(104) == 32_761
    assert layout_from_spec({"kind": "hex", "rings": 104, "pitch": 6.2}).shape == (32_761, 2)


def test_the_limit_follows_the_memory(monkeypatch):
    monkeypatch.setattr(layout_limits, "memory_limit", lambda: 1 * GIB)
    limit = robot_limit()
    assert limit == GIB // BYTES_PER_ROBOT
    rings = max(r for r in range(200) if hex_count(r) <= limit)
    assert len(layout_from_spec({"kind": "hex", "rings": rings, "pitch": 10.4})) == hex_count(rings)
    with pytest.raises(InputError, match=rf"layout.rings = {rings + 1} gives {hex_count(rings + 1)} robots"):
        layout_from_spec({"kind": "hex", "rings": rings + 1, "pitch": 10.4})
    xy = (np.arange(limit + 1)[:, None] * [1.0, 0.0]).tolist()
    with pytest.raises(InputError, match=rf"layout.xy = {limit + 1} points"):
        parse_problem({"layout": {"kind": "points", "xy": xy}, "kinematics": {"kind": "rotary", "arm": 0.1,
                       "steps": 4}, "collision": {"buffer": 0.0}, "start": [0] * (limit + 1),
                       "target": [0] * (limit + 1)}, where="p.json")


@pytest.mark.parametrize("rings", [10**9, 10**40])
def test_hostile_rings_are_refused_at_once(rings):
    start = time.process_time()
    spec = {"layout": {"kind": "hex", "rings": rings, "pitch": 10.4}, "preset": "desi",
            "kinematics": {"alpha_steps": 12, "beta_steps": 7}, "start": [], "target": []}
    with pytest.raises(InputError, match=rf"p.json: layout.rings = {rings} gives \d+ robots, more than"):
        parse_problem(spec, where="p.json")
    with pytest.raises(InputError, match=rf"rings = {rings} gives"):
        preset_problem("desi", rings=rings, start="folded")
    assert time.process_time() - start < 5  # refused before allocating (a generous bound)


def test_negative_or_fractional_rings_are_format_errors():
    with pytest.raises(FormatError, match="layout.rings must be a non-negative integer, got -1"):
        layout_from_spec({"kind": "hex", "rings": -1, "pitch": 1.0})
    with pytest.raises(InputError, match="rings must be a non-negative integer, got 2.5"):
        preset_problem("desi", rings=2.5)


def test_check_robot_count_names_field_and_value():
    check_robot_count(32_768, "layout", "32768 positioners", memory=16 * GIB)
    with pytest.raises(InputError, match="layout = 32769 positioners gives 32769 robots"):
        check_robot_count(32_769, "layout", "32769 positioners", memory=16 * GIB)


@pytest.mark.slow
def test_desi_at_65_rings():
    p = preset_problem("desi", rings=65, alpha_steps=13, beta_steps=7)
    assert p.n == hex_count(65) == 12_871
    assert not p.collisions(p.start) and not p.collisions(p.target)


@pytest.mark.parametrize("name, published, rings", [("spec-s5", 12_852, 65), ("must", 20_000, 82),
                                                    ("wst", 32_000, 103)])
def test_next_generation_presets(name, published, rings):
    pre = PRESETS[name]
    assert pre.rings == rings
    above = [r for r in range(200) if hex_count(r) >= published][0]
    nearest = min(range(200), key=lambda r: abs(hex_count(r) - published))
    assert rings == (above if pre.positioners.startswith(">") else nearest)
    assert "assumed: scaled from DESI's by pitch ratio" in pre.source
    assert pre.alpha == pytest.approx(3.0 * pre.pitch / 10.4, abs=1e-3)
    assert pre.buffer == pytest.approx(0.5 * pre.pitch / 10.4, abs=1e-3)
    p = preset_problem(name, rings=3, seed=1, alpha_steps=13, beta_steps=7)
    assert p.n == 37 and p.extra["preset"] == name
    with pytest.raises(InputError, match="has no whole focal plane"):
        preset_problem("desi", rings=None)


def _pairs_by_brute_force(xy, grow):
    d = np.linalg.norm(xy[:, None, :] - xy[None, :, :], axis=-1)
    a, b = np.nonzero((d < grow[:, None] + grow[None, :]) & (np.arange(len(xy))[:, None] < np.arange(len(xy))))
    return np.stack([a, b], axis=-1)


@pytest.mark.parametrize("seed", range(4))
def test_neighbour_pairs_are_the_brute_force_ones(seed):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-80, 80, (300, 2)) if seed else hex_grid(6, 10.4)
    reach, buffers = rng.uniform(0.5, 8, len(xy)), rng.uniform(0, 1, len(xy))
    assert np.array_equal(neighbour_pairs(xy, reach, buffers), _pairs_by_brute_force(xy, reach + buffers))


def _draw_robot_by_robot(kin, bases, buffer, rng):
    """The draw as the module docstring states it: every distance computed where the robots stand."""
    pairs = neighbour_pairs(bases, kin.reach, np.full(len(bases), buffer))
    positions = kin.all_positions()
    local = kin.segments(positions)
    conf, seg = np.zeros((len(bases), 2), dtype=int), np.zeros((len(bases), 2, 2))
    for p in range(len(bases)):
        free = np.ones(len(positions), dtype=bool)
        nb = pairs[pairs[:, 1] == p, 0]
        if len(nb):
            mine = local + bases[p]
            free &= np.all(segment_distance(mine[:, None, 0], mine[:, None, 1], seg[nb, 0], seg[nb, 1])
                           >= 2 * buffer, axis=1)
        k = int(rng.choice(np.nonzero(free)[0]))
        conf[p], seg[p] = positions[k], placed_segments(kin, bases[p], positions[k])
    return conf


@pytest.mark.parametrize("pitch, buffer, seed", [(10.4, 0.5, 0), (10.4, 0.0, 1), (6.0, 0.5, 2), (7.3, 1.0, 3)])
def test_the_draw_is_the_robot_by_robot_one(pitch, buffer, seed):
    kin = AlphaBeta(3.0, 3.0, 13, 7, (0.0, 180.0))
    bases = hex_grid(5, pitch)
    bases = bases + np.random.default_rng(seed).normal(0, 0.01, bases.shape) * (seed % 2)  # a grid, or nearly one
    fast = random_configuration(kin, bases, buffer, np.random.default_rng(seed))
    assert np.array_equal(fast, _draw_robot_by_robot(kin, bases, buffer, np.random.default_rng(seed)))
