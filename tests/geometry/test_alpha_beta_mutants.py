"""The alpha-beta lattice at its edges: a two-position beta joint, an alpha joint with hard
stops, an alpha angle table that does not fit in one turn.  Hand-written expected values.

Written for survivors of a uniform sample of the geometry module's mutants
(``benchmarks/mutation_run.py --sample 40 --seed 0 geometry``)."""

from __future__ import annotations

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.geometry.alpha_beta import AlphaBeta


def test_a_beta_joint_of_two_positions_is_accepted():
    kin = AlphaBeta(7.4, 15.0, 12, 2)
    assert kin.beta_steps == 2 and np.allclose(kin.lattice_deg(1), [0.0, 180.0])
    with pytest.raises(InputError, match="beta_steps must be an integer >= 2"):
        AlphaBeta(7.4, 15.0, 12, 1)


def test_an_alpha_joint_with_hard_stops_spans_its_range():
    kin = AlphaBeta(7.4, 15.0, 5, 7, alpha_range=(-170.0, 170.0))
    assert np.allclose(kin.lattice_deg(0), [-170.0, -85.0, 0.0, 85.0, 170.0])


def test_a_wrapping_alpha_table_must_fit_in_one_turn():
    AlphaBeta(7.4, 15.0, 4, 7, alpha_deg=[0.0, 90.0, 180.0, 350.0])  # the wrap step 350 -> 360 is 10 degrees
    with pytest.raises(InputError, match="within one turn"):
        AlphaBeta(7.4, 15.0, 4, 7, alpha_deg=[0.0, 90.0, 180.0, 400.0])
    # hard stops: no step across the wrap, so both ends of a whole turn are positions
    AlphaBeta(7.4, 15.0, 4, 7, alpha_range=(-180.0, 180.0), alpha_deg=[-180.0, 0.0, 90.0, 180.0])
    with pytest.raises(InputError, match="within one turn"):
        AlphaBeta(7.4, 15.0, 4, 7, alpha_deg=[-180.0, 0.0, 90.0, 180.0])
