"""The ASAP schedule's single-turn check reads eager swept tables bit by bit, with the same verdicts.

``_Asap._turn_hits`` answers "does ``p`` turning one joint hit a standing neighbour?" on eager
tables by reading one swept entry at a time on Python ints (stopping at the first hit); it must
say what :meth:`CollisionTables.swept_entries` of all the neighbours' entries at once says, for
every robot, joint, direction and random configuration (many colliding, many free).
"""

from __future__ import annotations

import numpy as np

from supcoord.planning.schedule import _Asap
from supcoord.problems.presets import preset_problem


def test_turn_hits_is_the_vectorised_swept_lookup():
    problem = preset_problem("sdss-v", rings=2, alpha_steps=8, beta_steps=5)
    tables = problem.tables()
    assert not tables.lazy
    kin = problem.kinematics
    asap = _Asap(problem, 1e-6)
    rng = np.random.default_rng(0)
    seen = set()
    for _ in range(60):
        asap.cur = np.array([[int(rng.integers(j.steps)) for j in kin.joints] for _ in range(problem.n)])
        for p in range(problem.n):
            standing = asap.nbrs[p]
            if not standing:
                continue
            for joint in range(kin.n_joints):
                for d in (-1, 1):
                    dp = np.zeros(kin.n_joints, dtype=np.int64)
                    dp[joint] = d
                    m = asap.move_index[(joint, d)]
                    i = kin.flat_position(asap.cur[p])
                    ks, sides = np.array([asap.pair_of[(p, q)] for q in standing]).T
                    js = np.array([kin.flat_position(asap.cur[q]) for q in standing])
                    want = bool(tables.swept_entries(ks, sides, m, np.where(sides == 0, i, js),
                                                     np.where(sides == 0, js, i)).any())
                    assert asap._turn_hits(p, dp, asap.cur[p], standing) == want
                    seen.add(want)
    assert seen == {True, False}
