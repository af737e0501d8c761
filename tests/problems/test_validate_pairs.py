"""The validator's neighbour candidates (bases closer than a limit) are every such pair, found without N² work."""

from __future__ import annotations

import numpy as np
import pytest

from supcoord.problems.validate_motion import _close_pairs


def _brute(bases, limit):
    a, b = np.nonzero(np.hypot(*(bases[:, None, :] - bases[None, :, :]).transpose(2, 0, 1)) < limit)
    return a[a < b], b[a < b]


@pytest.mark.parametrize("seed", range(6))
def test_close_pairs_are_those_of_every_distance(seed):
    rng = np.random.default_rng(seed)
    if seed % 2:  # random bases
        bases, limit = rng.uniform(0, 120, (int(rng.integers(2, 300)), 2)), float(rng.uniform(1, 25))
    else:  # a square lattice whose neighbours sit exactly at the limit: closer than it excludes them
        k = 12
        bases = np.stack(np.meshgrid(np.arange(k), np.arange(k)), -1).reshape(-1, 2) * 10.4
        limit = 10.4 * (1 + seed // 2)
    got, want = _close_pairs(bases, limit), _brute(bases, limit)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


def test_close_pairs_of_fewer_than_two_bases_are_none():
    for bases in (np.zeros((0, 2)), np.zeros((1, 2))):
        a, b = _close_pairs(bases, 5.0)
        assert len(a) == len(b) == 0
