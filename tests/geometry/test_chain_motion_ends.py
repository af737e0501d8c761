"""The one-motion checker's memoised end poses are the poses it used to compute, bit for bit.

:meth:`supcoord.geometry.chain_motion.ChainGeometry.ends` keeps, per position and delta, a
robot's segment at ``t = 0`` and ``t = 1`` relative to its base; placing it adds the base last,
as :func:`~supcoord.geometry.chain_motion._pose` does, so the placed end points (and hence the
end-point distances that decide most motions) must equal ``_pose``'s to the last bit, on
heterogeneous robots, wrapping joints and one- or two-joint deltas.
"""

from __future__ import annotations

import numpy as np
import pytest

from supcoord.geometry.chain_motion import _pose, chain_geometry

from .test_chain_motion_inline import _kinematics, _motion


@pytest.mark.parametrize("kind", range(4))
def test_ends_are_the_poses_at_both_ends(kind):
    rng = np.random.default_rng(kind)
    for _ in range(40):
        kin = _kinematics(rng, kind)
        geo = chain_geometry(kin)
        q, d = _motion(rng, kin, int(rng.integers(1, kin.n_joints + 1)))
        base = (float(rng.uniform(-500, 500)), float(rng.uniform(-500, 500)))
        ends = geo.ends(q, d)
        a0, b0 = geo.angles(q)
        a1, b1 = geo.angles(tuple(x + v for x, v in zip(q, d)))
        assert ends[:4] == (a0, a1 - a0, b0, b1 - b0)
        p = (base[0], base[1], geo.l1, geo.s0x, geo.s0y, geo.s1x, geo.s1y) + ends[:4]
        for t, local in ((0.0, ends[4:8]), (1.0, ends[8:12])):
            placed = (local[0] + base[0], local[1] + base[1], local[2] + base[0], local[3] + base[1])
            assert np.array(placed).view(np.int64).tolist() == np.array(_pose(p, t)).view(np.int64).tolist()
        assert geo.ends(q, d) is ends  # memoised
