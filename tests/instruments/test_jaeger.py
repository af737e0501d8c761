"""Plans in SDSS-V's jaeger format (supcoord.problems.jaeger) and the validator's check of such
a file as written (supcoord.problems.validate_jaeger), on an SDSS-V-like hex and on the APO wok."""

import json
from pathlib import Path

import numpy as np
import pytest

from supcoord.errors import FormatError, InputError
from supcoord.instruments import load_instrument
from supcoord.planning.planner import solve
from supcoord.problems.jaeger import jaeger_paths, write_jaeger
from supcoord.problems.plan import Plan
from supcoord.problems.problem import load_problem, parse_problem
from supcoord.problems.validate_jaeger import check_jaeger

EXAMPLE = Path(__file__).resolve().parents[2] / "docs" / "examples" / "sdss_v_exact.json"
FOLDED = [[10.0, 170.0]] * 500


@pytest.fixture(scope="module")
def hex_plan():
    problem = load_problem(EXAMPLE)
    plan = solve(problem, improve=0)
    assert plan.status == "complete"
    return problem, plan


@pytest.fixture(scope="module")
def apo():
    """The APO wok: every robot folded, robot 0 turning alpha by one step of its lattice."""
    still = parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-apo"}, "start": {"alpha_beta_deg": FOLDED},
                           "target": {"alpha_beta_deg": FOLDED}})
    target = [list(r) for r in FOLDED]
    target[0] = still.kin(0).joint_angles_deg(still.start[0] + np.array([1, 0])).tolist()
    problem = parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-apo"},
                             "start": {"alpha_beta_deg": FOLDED}, "target": {"alpha_beta_deg": target}})
    return problem, target[0], still


def _pieces(points):
    a = np.asarray(points, float)
    return np.diff(a[:, 0]) / np.diff(a[:, 1])


@pytest.mark.parametrize("acceleration", [None, 40.0])
@pytest.mark.parametrize("reverse", [False, True])
def test_export_follows_the_contract_and_passes_the_check(hex_plan, acceleration, reverse):
    problem, plan = hex_plan
    out = jaeger_paths(problem, plan, rpm=2, acceleration=acceleration, start_delay_s=1.0, reverse=reverse)
    ends = problem.angles_deg(problem.start), problem.angles_deg(problem.target)
    first, last = (ends[1], ends[0]) if reverse else ends
    assert sorted(out.paths, key=int) == [str(p) for p in range(problem.n)]
    for p in range(problem.n):
        for j, name in enumerate(("alpha", "beta")):
            pts = np.asarray(out.paths[str(p)][name], float)
            assert pts[0, 0] == first[p, j] and pts[-1, 0] == last[p, j]   # exactly, [deg, s]
            assert pts[0, 1] == 1.0 and np.all(np.diff(pts[:, 1]) > 0)
            v = _pieces(pts)
            assert np.all(np.abs(v) <= 12.0 * (1 + 1e-9))
            if acceleration is None and len(v) > 1:   # collinear points merged
                assert np.all(np.abs(np.diff(v)) > 1e-9)
            if acceleration is not None:   # from rest, and by at most acceleration * dt between pieces
                dt = np.diff(pts[:, 1])
                assert abs(v[0]) <= acceleration * dt[0] + 1e-9
                assert np.all(np.abs(np.diff(v)) <= acceleration * (dt[1:] + dt[:-1]) / 2 * (1 + 1e-9))
    res = check_jaeger(problem, out.to_json(), reverse=reverse)
    assert res.valid, res.problems
    assert res.collisions == 0 and res.max_speed_deg_s <= 12.0 * (1 + 1e-9)
    assert res.motion_time_s == pytest.approx(out.motion_time_s)


def test_acceleration_lengthens_the_motion(hex_plan):
    problem, plan = hex_plan
    fast = jaeger_paths(problem, plan, rpm=2)
    ramped = jaeger_paths(problem, plan, rpm=2, acceleration=40.0)
    assert ramped.motion_time_s > fast.motion_time_s and ramped.points > fast.points


def test_limits_are_refused_with_their_name(hex_plan):
    problem, plan = hex_plan
    with pytest.raises(InputError, match=r"in \(0, 3\]") as exc:
        jaeger_paths(problem, plan, rpm=3.5)
    assert exc.value.where == "rpm"
    with pytest.raises(InputError, match="needs a joint speed"):
        jaeger_paths(problem, plan)   # no instrument to take the speed from
    with pytest.raises(InputError, match="complete or partial plan"):
        jaeger_paths(problem, Plan("unknown"), rpm=2)


def test_write_never_over_an_input(hex_plan, tmp_path):
    problem, plan = hex_plan
    src = tmp_path / "problem.json"
    src.write_text(EXAMPLE.read_text())
    with pytest.raises(InputError, match="also an input"):
        write_jaeger(src, jaeger_paths(problem, plan, rpm=2), (src,))
    write_jaeger(tmp_path / "p.json", jaeger_paths(problem, plan, rpm=2), (src,))
    assert json.loads((tmp_path / "p.json").read_text())["0"]["alpha"][0][1] == 0.0


def test_instrument_keys_and_defaults(apo):
    problem, target, _ = apo
    ids = load_instrument("sdss-v-apo").positioner_ids
    plan = Plan("complete", [problem.start, problem.target])
    out = jaeger_paths(problem, plan)
    assert set(out.paths) == {str(i) for i in ids}
    alpha = out.paths[str(ids[0])]["alpha"]
    turn = abs(target[0] - 10.0)
    assert alpha == [[10.0, 1.0], [target[0], 1.0 + turn / 12.0]]     # 2 RPM, 1 s delay, two points
    assert check_jaeger(problem, out.to_json()).valid


def _opening(problem, key, t_open=2.0):
    """Robot ``key`` opens beta to 0 deg and folds back: across its neighbours' folded arms."""
    return {key: {"alpha": [[10.0, 1.0]], "beta": [[170.0, 1.0], [0.0, 1.0 + t_open], [170.0, 1.0 + 2 * t_open]]}}


def test_a_colliding_hand_made_path_is_caught(apo):
    _, _, folded = apo
    ids = load_instrument("sdss-v-apo").positioner_ids
    key = str(ids[100])
    res = check_jaeger(folded, _opening(folded, key))
    assert not res.valid and res.collisions >= 1
    first = res.first
    assert key in first["positioner_ids"] and 100 in first["robots"]
    assert 1.0 < first["time_s"] < 5.0 and first["clearance_mm"] < 0
    assert first["distance_mm"] < first["required_mm"]
    # the same robot opening only to beta 160 passes: the check is not a blanket refusal
    calm = {key: {"alpha": [[10.0, 1.0]], "beta": [[170.0, 1.0], [160.0, 2.0], [170.0, 3.0]]}}
    assert check_jaeger(folded, calm).valid


def test_speed_over_the_limit_is_reported(apo):
    _, _, folded = apo
    key = str(load_instrument("sdss-v-apo").positioner_ids[0])
    fast = {key: {"alpha": [[10.0, 1.0]], "beta": [[170.0, 1.0], [160.0, 1.5], [170.0, 2.0]]}}   # 20 deg/s
    res = check_jaeger(folded, fast)
    assert not res.valid and res.collisions == 0 and res.max_speed_deg_s == pytest.approx(20.0)
    assert any("faster than the limit 18" in p for p in res.problems)
    assert check_jaeger(folded, fast, max_rpm=4).valid


@pytest.mark.parametrize("bad, match", [
    ({}, "non-empty object"),
    ({"99999": {"alpha": [[10, 1]], "beta": [[170, 1]]}}, "not a positioner ID"),
    ("KEY", "must be \\{\"alpha\""),
    ({"KEY": {"alpha": [[10, 1], [20, 1]], "beta": [[170, 1]]}}, r"KEY\.alpha\[1\]: times must increase"),
    ({"KEY": {"alpha": [[10, "x"]], "beta": [[170, 1]]}}, r"KEY\.alpha\[0\] must be \[deg, s\]"),
])
def test_malformed_files_name_the_place(apo, bad, match):
    problem, _, _ = apo
    key = str(load_instrument("sdss-v-apo").positioner_ids[0])
    if bad == "KEY":
        bad = {key: {"alpha": [[10, 1]]}}
    bad = json.loads(json.dumps(bad).replace("KEY", key))
    with pytest.raises(FormatError, match=match.replace("KEY", key)):
        check_jaeger(problem, bad)


def test_reads_jaegers_dump_and_files(apo, tmp_path):
    problem, _, _ = apo
    plan = Plan("complete", [problem.start, problem.target])
    paths = jaeger_paths(problem, plan).to_json()
    f = tmp_path / "dump.json"
    f.write_text(json.dumps({"success": True, "trajectory": paths}))
    assert check_jaeger(problem, f).valid
    with pytest.raises(FormatError, match="bad.json: not valid JSON"):
        (tmp_path / "bad.json").write_text("{")
        check_jaeger(problem, tmp_path / "bad.json")


def _cli(*argv):
    import contextlib
    import io

    from supcoord.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def test_cli_solve_exports_and_check_validates(tmp_path):
    paths, back = tmp_path / "paths.json", tmp_path / "back.json"
    code, out, err = _cli("solve", str(EXAMPLE), "--improve", "0", "--jaeger", str(paths), "--jaeger-reverse",
                          str(back), "--rpm", "2", "--start-delay", "1", "--json")
    assert code == 0, err
    assert json.loads(out)["collision"]["definition"] == "problem"
    assert json.loads(paths.read_text())["0"]["alpha"][0] == [10.0, 1.0]
    code, out, err = _cli("check", str(EXAMPLE), "--jaeger", str(paths), "--json")
    assert code == 0 and json.loads(out)["valid"] is True, out
    code, out, _ = _cli("check", str(EXAMPLE), "--jaeger", str(back), "--reverse")
    assert code == 0 and out.startswith("VALID"), out
    code, out, _ = _cli("check", str(EXAMPLE), "--jaeger", str(back))   # back is not the way there
    assert code == 0 and out.startswith("INVALID"), out


@pytest.mark.parametrize("argv, where", [
    (["solve", str(EXAMPLE), "--jaeger", "P", "--rpm", "4"], "--rpm: must be a speed in RPM in (0, 3]"),
    (["solve", str(EXAMPLE), "--jaeger", "P"], "--rpm: needs a joint speed in RPM"),
    (["solve", str(EXAMPLE), "--jaeger", str(EXAMPLE), "--rpm", "2"], "--jaeger: "),
    (["check", str(EXAMPLE)], "give a PLAN.json or --jaeger"),
    (["check", str(EXAMPLE), "--jaeger", "MISSING"], "jaeger trajectory file not found"),
])
def test_cli_mistakes_are_one_line_exit_2(tmp_path, argv, where):
    argv = [a.replace("P", str(tmp_path / "p.json")) if a == "P" else
            a.replace("MISSING", str(tmp_path / "none.json")) if a == "MISSING" else a for a in argv]
    code, out, err = _cli(*argv)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and where in err, err
    assert not (tmp_path / "p.json").exists()


def test_offline_robots_are_left_out():
    data = json.loads(EXAMPLE.read_text())
    data["offline"] = {"5": [10.0, 170.0]}
    problem = parse_problem(data)
    plan = solve(problem, improve=0)
    assert plan.status == "complete"
    out = jaeger_paths(problem, plan, rpm=2)
    assert "5" not in out.paths and len(out.paths) == problem.n - 1
    assert check_jaeger(problem, out.to_json()).valid   # the check holds an unlisted robot at its start
