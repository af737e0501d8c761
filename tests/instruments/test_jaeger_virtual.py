"""supcoord's jaeger export through jaeger's own trajectory code to jaeger's virtual robots.

Needs SDSS-V's robot controller ``jaeger`` (PyPI), which is not a test dependency: it pins
``numpy<2`` and ``sdss-kaiju==1.4.0b1`` (an sdist that fetches files at build time) and
brings some sixty packages (database drivers, astropy, a message broker client), so it is
installed beside supcoord only where wanted.  Without it the test is skipped and says so.
``benchmarks/jaeger_virtual.py`` runs (jaeger's ``send_trajectory`` to a ``VirtualFPS``) in a
process of its own, so that jaeger's background tasks cannot outlive the test.
"""

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

if importlib.util.find_spec("jaeger") is None:
    pytest.skip("jaeger (SDSS-V's robot controller, PyPI 'jaeger') is not installed; it is not a test dependency "
                "(it pins numpy<2)", allow_module_level=True)

from supcoord.problems.jaeger import jaeger_paths  # noqa: E402
from supcoord.problems.plan import Plan  # noqa: E402
from supcoord.problems.problem import parse_problem  # noqa: E402

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "jaeger_virtual.py"
FOLDED = [[10.0, 170.0]] * 500


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_jaeger_accepts_the_export_and_the_virtual_robots_end_at_their_targets(tmp_path):
    still = parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-apo"},
                           "start": {"alpha_beta_deg": FOLDED}, "target": {"alpha_beta_deg": FOLDED}})
    target = [list(r) for r in FOLDED]
    for p in (0, 1):   # two robots turn alpha by one step of their lattices, robot 2 stands still
        target[p] = still.kin(p).joint_angles_deg(still.start[p] + np.array([1, 0])).tolist()
    data = {"layout": {"kind": "instrument", "name": "sdss-v-apo"}, "start": {"alpha_beta_deg": FOLDED},
            "target": {"alpha_beta_deg": target}}
    problem = parse_problem(data)
    exported = jaeger_paths(problem, Plan("complete", [problem.start, problem.target])).paths
    keys = list(exported)[:3]
    (tmp_path / "problem.json").write_text(json.dumps(data))
    (tmp_path / "paths.json").write_text(json.dumps({k: exported[k] for k in keys}))
    run = subprocess.run([sys.executable, str(BENCH), str(tmp_path / "problem.json"), str(tmp_path / "paths.json"),
                          "--out", str(tmp_path / "res.json")], capture_output=True, text=True, timeout=280,
                         env=dict(os.environ, OBSERVATORY="APO"))
    assert run.returncode == 0, run.stderr[-3000:]
    res = json.loads((tmp_path / "res.json").read_text())
    assert res["entry_point"].startswith("jaeger.commands.trajectory.send_trajectory(")
    assert res["accepted"] and res["received_robots"] == 3 and res["decoded_times_increase"]
    assert res["at_targets"] and res["max_end_error_deg"] < 1e-6
    assert res["decoded_max_angle_error_deg"] < 1e-6 and res["decoded_max_time_error_s"] <= 0.0005
