"""Hard wok fields (``supcoord.instruments.hard_fields``): seeded, valid, and what each kind promises."""

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.geometry.segments import segment_distance
from supcoord.instruments import fibre_xy, load_instrument, robot_forward
from supcoord.instruments.hard_fields import (CLOSE_RADIUS_MM, KINDS, hard_wok_field, unreachable_certificate)
from supcoord.instruments.sdss_v import FIDUCIAL_WATCH
from supcoord.problems.problem import parse_problem

APO = "sdss-v-apo"


@pytest.fixture(scope="module")
def fields():
    return {kind: hard_wok_field(APO, seed=3, kind=kind, count=1 if kind != "close" else 2) for kind in KINDS}


def test_the_same_seed_gives_the_same_field_and_another_seed_another(fields):
    again = hard_wok_field(APO, seed=3, kind="close", count=2)
    assert np.array_equal(again.target, fields["close"].target) and again.clusters == fields["close"].clusters
    other = hard_wok_field(APO, seed=4, kind="close", count=2)
    assert not np.array_equal(other.target, fields["close"].target)


@pytest.mark.slow  # reads a 500-robot wok problem per field: seconds
@pytest.mark.parametrize("kind", KINDS)
def test_every_field_is_a_problem_the_reader_accepts(fields, kind):
    f = fields[kind]
    prob = parse_problem(f.problem())          # refuses a colliding start or target
    assert prob.n == 500 and set(prob.held) == set(f.offline)
    for p, ab in f.offline.items():
        assert tuple(f.start[p]) == tuple(f.target[p]) == ab
    moving = np.setdiff1d(np.arange(500), list(f.offline))
    assert np.all(f.start[moving] == [10.0, 170.0])
    assert np.all((f.target[:, 1] >= 0) & (f.target[:, 1] <= 180))


def test_an_offline_arm_reaches_into_a_neighbours_elbow_circle(fields):
    geom = load_instrument(APO)
    (b, (a, beta)), = fields["offline"].offline.items()
    seg = robot_forward(geom, b, a, beta)
    d = segment_distance(seg[0], seg[1], geom.bases, geom.bases)
    d[b] = np.inf
    near = np.flatnonzero(d <= geom.alpha_arm + 2 * geom.robot_buffer)
    assert len(near) >= 1


def test_a_close_cluster_puts_its_fibres_in_one_small_disc(fields):
    f = fields["close"]
    geom = load_instrument(APO)
    assert len(f.clusters) == 2
    for members in f.clusters:
        assert len(members) >= 3
        xy = np.array([fibre_xy(geom, p, *f.target[p], "metrology") for p in members])
        assert np.linalg.norm(xy[:, None] - xy[None], axis=-1).max() <= 2 * CLOSE_RADIUS_MM + 1e-9


def test_an_unreachable_target_is_certified_and_the_certificate_rests_on_the_offline_arm(fields):
    f = fields["unreachable"]
    assert len(f.certificates) >= 1
    c = f.certificates[0]
    assert c.blockers == tuple(sorted(f.offline)) and c.relax_mm > c.bound_mm > 0
    assert tuple(f.target[c.robot]) == c.target
    assert unreachable_certificate(APO, c.robot, c.start, c.target, f.offline) == c
    # without the offline robots the same robot reaches the same target: the arm is the cause
    assert unreachable_certificate(APO, c.robot, c.start, c.target, {}) is None
    # and its own start is reachable from its start
    assert unreachable_certificate(APO, c.robot, c.start, c.start, f.offline) is None


def test_the_certificate_agrees_with_a_walk_along_alpha_that_the_offline_arm_stops():
    """Independent of the grid: sweep the robot's alpha from start to target at every beta of a
    coarse set; with the certified robot every sweep collides with the offline arm somewhere."""
    f = hard_wok_field(APO, seed=5, kind="unreachable", count=1)
    geom = load_instrument(APO)
    c = f.certificates[0]
    (b, pose), = [(q, f.offline[q]) for q in c.blockers if q in f.offline][:1]
    arm = robot_forward(geom, b, *pose)
    lo, hi = sorted((c.start[0], c.target[0]))
    alphas = np.linspace(lo, hi, 2000)
    for beta in np.linspace(0, 360, 37):
        seg = robot_forward(geom, np.full(len(alphas), c.robot), alphas, np.full(len(alphas), beta))
        d = segment_distance(seg[:, 0], seg[:, 1], arm[0], arm[1])
        assert d.min() < 2 * geom.robot_buffer, beta


def test_fiducial_watch_robots_are_never_taken_offline():
    geom = load_instrument(APO)
    for seed in range(3):
        f = hard_wok_field(APO, seed=seed, kind="offline", count=2)
        assert not any(geom.fiducial_watch[p] for p in f.offline)
        for p, (a, b) in f.offline.items():
            assert b >= FIDUCIAL_WATCH[0] + FIDUCIAL_WATCH[1] * a or not geom.fiducial_watch[p]


@pytest.mark.parametrize("kwargs", [{"kind": "crowded"}, {"seed": -1}, {"seed": True}, {"count": 0},
                                    {"count": 51}, {"count": 1.5}])
def test_bad_arguments_are_input_errors(kwargs):
    with pytest.raises(InputError):
        hard_wok_field(APO, **kwargs)
