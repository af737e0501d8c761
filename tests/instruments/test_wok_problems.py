"""Writing problems on a real wok: the helpers of supcoord.instruments.wok, where "fibre" may be
written, radians read as degrees, and `supcoord check` with its files swapped."""

from __future__ import annotations

import json

import numpy as np
import pytest

import supcoord as sc
from supcoord.cli.main import main
from supcoord.errors import InputError
from supcoord.geometry.segments import segment_distance
from supcoord.instruments import fibre_xy, load_instrument, robot_forward
from supcoord.instruments.wok import _collided, _neighbours

APO = "sdss-v-apo"


@pytest.fixture(scope="module")
def geom():
    return load_instrument(APO)


@pytest.fixture(scope="module")
def targets(geom):
    return sc.random_wok_targets(geom, seed=3)


@pytest.mark.slow  # reads a 500-robot wok problem: seconds
def test_random_targets_are_seeded_in_range_and_collision_free(geom, targets):
    assert targets.shape == (500, 2)
    assert np.all((targets[:, 0] >= 0) & (targets[:, 0] < 360) & (targets[:, 1] >= 0) & (targets[:, 1] <= 180))
    assert np.array_equal(targets, sc.random_wok_targets(APO, seed=3))
    assert not np.array_equal(targets, sc.random_wok_targets(APO, seed=4))
    # independently of _collided: every neighbour pair at least kaiju's 4.0782 mm apart (4 mm plus
    # its 0.1 deg step margin, the wok's default definition), every obstacle 5 mm
    seg = robot_forward(geom, np.arange(500), targets[:, 0], targets[:, 1])
    a, b = np.triu_indices(500, 1)
    near = np.linalg.norm(geom.bases[a] - geom.bases[b], axis=1) < 60
    a, b = a[near], b[near]
    assert segment_distance(seg[a, 0], seg[a, 1], seg[b, 0], seg[b, 1]).min() >= 4.0782
    d_obs = segment_distance(seg[:, None, 0], seg[:, None, 1], geom.obstacles[None, :, 0], geom.obstacles[None, :, 1])
    assert (d_obs - geom.obstacle_buffers[None]).min() >= 2.0


def test_the_collision_rule_finds_what_a_first_draw_has(geom):
    rng = np.random.default_rng(0)
    from supcoord.instruments.wok import _draw

    first = _draw(geom, np.arange(500), "metrology", rng)
    assert _collided(geom, first, _neighbours(geom)).sum() > 10   # a random draw collides: decollision matters


@pytest.mark.slow  # reads a 500-robot wok problem: seconds
def test_the_problem_reader_accepts_the_helpers_output(targets):
    problem = sc.parse_problem(sc.wok_problem(APO, sc.folded_configuration(APO), targets, name="t"))
    assert problem.n == 500 and problem.warnings == [] and problem.extra["name"] == "t"
    assert np.allclose(problem.angles_deg(problem.target), targets, atol=1e-9)


def test_targets_by_positioner_id(geom):
    pid = geom.positioner_ids[7]
    xy = fibre_xy(geom, 7, 40.0, 100.0, "apogee")
    ab = sc.wok_targets(APO, {str(pid): xy.tolist()}, fibre="apogee")
    assert np.allclose(ab[7], [40.0, 100.0]) and np.all(ab[np.arange(500) != 7] == [10.0, 170.0])
    ab = sc.wok_targets(APO, {pid: [400.0, 100.0]}, form="alpha_beta_deg")
    assert ab[7].tolist() == [40.0, 100.0]
    with pytest.raises(InputError, match="not a positioner ID"):
        sc.wok_targets(APO, {999999: [0.0, 0.0]})
    with pytest.raises(InputError, match=f"targets\\[{pid}\\]: boss fibre position .* outside its reach"):
        sc.wok_targets(APO, {pid: (geom.bases[7] + 40).tolist()})
    with pytest.raises(InputError, match="beta 200.000 deg is outside"):
        sc.wok_targets(APO, {pid: [10, 200]}, form="alpha_beta_deg")
    boss_only = geom.positioner_ids[int(np.flatnonzero(~geom.has_apogee)[0])]
    with pytest.raises(InputError, match="no APOGEE fibre"):
        sc.wok_targets(APO, {boss_only: [0.0, 0.0]}, fibre="apogee")
    with pytest.raises(InputError, match="fibre must be one of"):
        sc.random_wok_targets(APO, fibre="red")


def _apogee_problem(geom, where: str) -> dict:
    """Robot 7 to an APOGEE-fibre position, the others folded, with "fibre" written at ``where``."""
    ab = sc.folded_configuration(geom)
    ab[7] = (40.0, 100.0)
    xy = fibre_xy(geom, np.arange(500), ab[:, 0], ab[:, 1], "apogee")
    d = {"layout": {"kind": "instrument", "name": APO}, "start": {"alpha_beta_deg": sc.folded_configuration().tolist()},
         "target": {"xy_mm": xy.tolist()}}
    if where == "top":
        d["fibre"] = "apogee"
    elif where:
        d[where]["fibre"] = "apogee"
    return d


@pytest.mark.slow  # reads a 500-robot wok problem: seconds
@pytest.mark.parametrize("where", ["top", "layout", "target"])
def test_fibre_has_one_meaning_wherever_it_is_written(geom, where):
    problem = sc.parse_problem(_apogee_problem(geom, where))
    assert problem.warnings == [] and problem.layout["fibre"] == "apogee"
    assert np.allclose(problem.angles_deg(problem.target)[7], [40.0, 100.0], atol=1e-6)


def test_fibre_conflicts_and_misplaced_fibres_are_errors(geom):
    d = _apogee_problem(geom, "top")
    d["layout"]["fibre"] = "boss"
    with pytest.raises(InputError, match="fibre is 'apogee' but layout.fibre is 'boss'"):
        sc.parse_problem(d)
    d = _apogee_problem(geom, "")
    d["target"]["fibre"] = ["apogee"]
    with pytest.raises(InputError, match="target.fibre must be one of metrology, apogee, boss"):
        sc.parse_problem(d)
    hexp = {"layout": {"kind": "hex", "rings": 1, "pitch": 22.4}, "kinematics": {"kind": "rotary", "arm": 15.0,
            "steps": 12}, "collision": {"buffer": 2.0}, "start": [0] * 7, "target": [0] * 7, "fibre": "boss"}
    with pytest.raises(InputError, match="only an instrument layout has named fibres"):
        sc.parse_problem(hexp)


def _one_robot(target) -> dict:
    return {"layout": {"kind": "points", "xy": [[0, 0]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7},
            "collision": {"buffer": 2.0}, "start": {"alpha_beta_deg": [[10.0, 170.0]]},
            "target": {"alpha_beta_deg": [target]}, "bogus": 1}


def test_radians_and_unknown_fields_warn():
    w = sc.parse_problem(_one_robot([0.7, 2.5])).warnings
    assert any("unknown field 'bogus'" in x for x in w)
    assert any("target.alpha_beta_deg" in x and "radians?" in x for x in w)
    for degrees in ([40.0, 100.0], [3.0, 5.0], [0.0, 0.0]):   # degrees, whole small numbers, all zero
        assert not any("radians" in x for x in sc.parse_problem(_one_robot(degrees)).warnings)
    with pytest.raises(InputError, match="outside the beta range .*radians\\?"):
        sc.parse_problem(_one_robot([0.7, -0.5]))


def test_check_with_its_files_swapped_says_so(tmp_path, capsys):
    problem = tmp_path / "problem.json"
    problem.write_text(json.dumps({k: v for k, v in _one_robot([40.0, 100.0]).items() if k != "bogus"}))
    plan = tmp_path / "plan.json"
    assert main(["solve", str(problem), "--out", str(plan), "-q"]) == 0
    capsys.readouterr()
    assert main(["check", str(plan), str(problem)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "looks like a PLAN (it has 'configurations')" in err
    assert f"{problem} looks like a PROBLEM" in err and "usage: supcoord check PROBLEM.json PLAN.json" in err
    assert main(["check", str(problem), str(plan)]) == 0
