"""The validator's list of robots in a message: the first ten, then how many in all."""

from __future__ import annotations

import numpy as np
import pytest

from supcoord.problems import Plan, parse_problem, validate_plan


@pytest.mark.parametrize("n", [3, 10, 11, 12])
def test_robots_not_at_target_are_listed_up_to_ten(n):
    problem = parse_problem({
        "layout": {"kind": "points", "xy": [[100.0 * i, 0.0] for i in range(n)]},
        "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
        "collision": {"buffer": 2.0},
        "start": [0] * n,
        "target": [6] * n,
    }, "row.json")
    result = validate_plan(problem, Plan("complete", [np.zeros((n, 1), dtype=np.int64)]))
    shown = ", ".join(str(i) for i in range(min(n, 10))) + (f", ... ({n} in all)" if n > 10 else "")
    assert not result.valid
    assert f"the last configuration is not the target (positioners {shown} are not at target)" in result.problems
