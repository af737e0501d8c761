"""An instrument layout brings its own collision definition (SDSS-V: kaiju's) as the default."""

import math

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.instruments import collision_definition, load_instrument, motion_limits, robot_collision_distance
from supcoord.problems.plan import Plan
from supcoord.problems.problem import parse_problem

FOLDED = [[10.0, 170.0]] * 500


def _problem(collision=None, name="sdss-v-apo"):
    data = {"layout": {"kind": "instrument", "name": name}, "start": {"alpha_beta_deg": FOLDED},
            "target": {"alpha_beta_deg": FOLDED}}
    if collision is not None:
        data["collision"] = collision
    return parse_problem(data)


@pytest.fixture(scope="module")
def default_problem():
    return _problem()


def test_sdss_v_definition_is_kaijus_at_its_step():
    d = collision_definition("sdss-v-lco")
    g = load_instrument("sdss-v-lco")
    assert d.name == "sdss-v kaiju"
    assert 2 * d.buffer_mm + d.margin_mm == pytest.approx(robot_collision_distance(g, 0.1), abs=1e-15)
    assert round(2 * d.buffer_mm + d.margin_mm, 4) == 4.0782
    assert d.obstacle_margin_mm == 0.0 and d.ang_step_deg == 0.1
    m = motion_limits("sdss-v-apo")
    assert (m.rpm, m.max_rpm, m.speed_deg_s, m.max_speed_deg_s, m.start_delay_s) == (2.0, 3.0, 12.0, 18.0, 1.0)
    with pytest.raises(InputError, match="unknown instrument"):
        collision_definition("sdss-v-xyz")


def test_default_problem_uses_kaijus_distances(default_problem):
    p = default_problem
    # two robots: 4.0 mm + kaiju's 0.1 deg step margin; a robot and a fiducial or GFA: 2 + 3 mm
    assert np.allclose(p.buffers[:, None] + p.buffers[None, :], 4.0 + 2 * math.sin(math.radians(0.1)) * 22.4)
    assert np.allclose(p.buffers[0] + p.obstacle_buffers, 5.0)
    assert p.collision_statement() == {"definition": "sdss-v kaiju", "buffer_mm": 2.0,
                                       "margin_mm": collision_definition("sdss-v-apo").margin_mm,
                                       "obstacle_margin_mm": 0.0}


def test_plan_json_states_the_definition(default_problem):
    plan = Plan("complete", [default_problem.start, default_problem.target])
    assert plan.to_json(default_problem)["collision"]["definition"] == "sdss-v kaiju"


@pytest.mark.slow  # reads the 500-robot wok problem again: seconds
def test_round_trip_keeps_the_definition(default_problem):
    again = parse_problem(default_problem.to_json())
    assert again.collision_statement() == default_problem.collision_statement()
    assert np.array_equal(again.buffers, default_problem.buffers)
    assert np.array_equal(again.obstacle_buffers, default_problem.obstacle_buffers)


@pytest.mark.slow  # reads the 500-robot wok problem twice: seconds
def test_a_user_margin_replaces_the_definition():
    p = _problem({"margin": 0.0})
    assert p.collision_statement()["definition"] == "problem"
    assert np.allclose(p.buffers, 2.0) and np.allclose(p.buffers[0] + p.obstacle_buffers, 5.0)
    q = _problem({"margin": 0.5})  # a margin given alone applies to obstacles too (formats.md)
    assert np.allclose(q.buffers, 2.25) and np.allclose(q.buffers[0] + q.obstacle_buffers, 5.5)
    assert q.collision_statement() == {"definition": "problem", "buffer_mm": 2.0, "margin_mm": 0.5,
                                       "obstacle_margin_mm": 0.5}
