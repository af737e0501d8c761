"""The segment distance with shared differences gives the four point–segment distances'
numbers bit for bit (the reference below is the formula written out with one ``_psd`` per
end point, as the tables computed it before)."""

import numpy as np
import pytest

from supcoord.geometry import segments
from supcoord.geometry.chain_motion import segment_distance_floats


def _reference(ax, ay, bx, by, cx, cy, dx, dy):
    psd = segments._psd
    d = np.minimum(np.minimum(psd(ax, ay, cx, cy, dx, dy), psd(bx, by, cx, cy, dx, dy)),
                   np.minimum(psd(cx, cy, ax, ay, bx, by), psd(dx, dy, ax, ay, bx, by)))
    ux, uy, vx, vy = bx - ax, by - ay, dx - cx, dy - cy
    o1 = ux * (cy - ay) - uy * (cx - ax)
    o2 = ux * (dy - ay) - uy * (dx - ax)
    o3 = vx * (ay - cy) - vy * (ax - cx)
    o4 = vx * (by - cy) - vy * (bx - cx)
    return np.where((o1 * o2 < 0) & (o3 * o4 < 0), 0.0, d)


def _coords(seed: int, n: int = 4000) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    c = [rng.normal(0.0, 10.0, n) for _ in range(8)]
    c[2][:200], c[3][:200] = c[0][:200], c[1][:200]  # point-like first segment
    c[6][200:400], c[7][200:400] = c[4][200:400], c[5][200:400]  # point-like second segment
    c[4][400:600], c[5][400:600] = c[0][400:600], c[1][400:600]  # a shared end point
    t = rng.uniform(0.0, 1.0, 200)  # second segment starting on the first: touching, not crossing
    c[4][600:800] = c[0][600:800] + t * (c[2][600:800] - c[0][600:800])
    c[5][600:800] = c[1][600:800] + t * (c[3][600:800] - c[1][600:800])
    for k in range(8):  # collinear, on a lattice of exact values
        c[k][800:1000] = np.round(c[k][800:1000])
    c[1][800:1000], c[3][800:1000], c[5][800:1000], c[7][800:1000] = 0.0, 0.0, 0.0, 0.0
    return c


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_shared_differences_are_bitwise_the_reference(seed):
    c = _coords(seed)
    new, ref = segments.segment_distance_xy(*c), _reference(*c)
    assert np.array_equal(new.view(np.int64), ref.view(np.int64))
    # blocks (long inputs) and broadcasting give the same numbers
    long = [np.tile(v, 5) for v in c]
    assert np.array_equal(segments.segment_distance_xy(*long), np.tile(ref, 5))
    p0, p1 = np.stack(c[0:2], -1)[:50, None], np.stack(c[2:4], -1)[:50, None]
    q0, q1 = np.stack(c[4:6], -1)[None, :60], np.stack(c[6:8], -1)[None, :60]
    grid = _reference(*(np.broadcast_to(v, (50, 60)) for v in (p0[..., 0], p0[..., 1], p1[..., 0], p1[..., 1],
                                                               q0[..., 0], q0[..., 1], q1[..., 0], q1[..., 1])))
    assert np.array_equal(segments.segment_distance(p0, p1, q0, q1), grid)


def test_scalars_and_the_float_kernel_agree():
    c = _coords(3, 1000)
    for k in range(1000):
        v = [float(x[k]) for x in c]
        assert float(segments.segment_distance_xy(*v)) == float(_reference(*v)) == segment_distance_floats(*v)


def test_verdicts_at_the_threshold_do_not_flip():
    """Entries whose distance is exactly a threshold keep ``d < r`` False and ``d <= r`` True."""
    c = _coords(4)
    r = _reference(*c)
    new = segments.segment_distance_xy(*c)
    assert not (new < r).any() and (new <= r).all()
