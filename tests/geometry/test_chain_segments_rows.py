"""``chain_segments`` writes each end point's coordinates into place: the numbers of the
formula written with trailing length-2 axes and ``np.stack`` (as before), bit for bit, for
shared and per-entry links and segments, scalars and broadcast grids."""

import numpy as np
import pytest

from supcoord.geometry.chain import chain_segments


def _stacked(l1, segment, a, b):
    a, b, l1 = np.asarray(a, float), np.asarray(b, float), np.asarray(l1, float)
    s = np.asarray(segment, float)
    ex, ey = (l1 * np.cos(a))[..., None], (l1 * np.sin(a))[..., None]
    c, sn = np.cos(a + b)[..., None], np.sin(a + b)[..., None]
    x = ex + (s[..., 0] * c - s[..., 1] * sn)
    y = ey + (s[..., 0] * sn + s[..., 1] * c)
    return np.stack([x, y], axis=-1)


def _same(x, y):
    return x.shape == y.shape and np.array_equal(np.ascontiguousarray(x).view(np.int64),
                                                 np.ascontiguousarray(y).view(np.int64))


@pytest.mark.parametrize("seed", [0, 1])
def test_in_place_rows_are_bitwise_the_stacked_formula(seed):
    rng = np.random.default_rng(seed)
    n = 3000
    a, b = rng.uniform(-7.0, 7.0, n), rng.uniform(-4.0, 4.0, n)
    seg = np.array([[0.5, -0.3], [14.7, 0.2]])
    cases = [(7.4, seg, a, b), (0.0, seg, 0.0, b), (rng.uniform(7, 8, n), rng.normal(0, 5, (n, 2, 2)), a, b),
             (7.4, seg, a[:40, None], b[None, :30]), (7.4, seg, 1.25, -0.5),
             (7.4, rng.normal(0, 5, (30, 2, 2)), a[:1], b[:1])]
    for args in cases:
        assert _same(chain_segments(*args), _stacked(*args))
