"""``supcoord supcon``: formats.md JSON, exit statuses, export, agreement with libFAUDES
(files written by libFAUDES itself and by supcoord), libFAUDES's conventions
(controllability from the plant, specification-only events), the explicit and symbolic
routes giving the same supervisor, once through a subprocess."""

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import faudes
import pytest
from hypothesis import given, settings
from oracle import faudes_supcon, from_faudes, to_faudes
from strategies import systems

from supcoord.cli.main import main
from supcoord.des import explicit_ops as X
from supcoord.des.generator import Event, Generator
from supcoord.des.io import write_generator

KEYS = {"status", "states", "transitions", "marked", "bdd_nodes", "seconds"}


def run_cli(capsys, *argv):
    code = main(["supcon", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def small_factory_files(directory: Path, writer="faudes"):
    M1 = Generator.from_tct(3, [(0, 11, 1), (1, 10, 0), (1, 12, 2), (2, 13, 0)], 0, [0], "MACH1")
    M2 = Generator.from_tct(3, [(0, 21, 1), (1, 20, 0), (1, 22, 2), (2, 23, 0)], 0, [0], "MACH2")
    BUF = Generator.from_tct(2, [(0, 10, 1), (1, 21, 0)], 0, [0], "BUF")
    BR = Generator.from_tct(2, [(0, 22, 1), (1, 23, 0), (0, 13, 0)], 0, [0], "BR")
    paths = {}
    for g in (M1, M2, BUF, BR):
        path = directory / f"{g.name}.gen"
        if writer == "faudes":
            to_faudes(g).Write(str(path))
        else:
            write_generator(g, path)
        paths[g.name] = path
    return paths, (M1, M2), (BUF, BR)


@pytest.mark.parametrize("writer,route", [("faudes", "auto"), ("supcoord", "auto"), ("faudes", "explicit")])
def test_small_factory_json_and_export(tmp_path, capsys, writer, route):
    paths, plants, specs = small_factory_files(tmp_path, writer)
    out_file = tmp_path / "V.gen"
    code, out, err = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"],
                             "--export", out_file, "--json", "--route", route)
    assert code == 0, err
    payload = json.loads(out)
    assert set(payload) == KEYS | ({"effort"} if route != "explicit" else set())  # effort: the symbolic route's
    assert payload["status"] == "ok"
    assert (payload["states"], payload["transitions"], payload["marked"]) == (12, 24, 1)
    assert (payload["bdd_nodes"] > 0) == (route != "explicit") and payload["seconds"] >= 0
    exported = from_faudes(faudes.System(str(out_file)))  # libFAUDES reads what we wrote
    oracle = faudes_supcon(X.sync(*plants), X.sync(*specs))
    assert Generator(exported.n_states, oracle.alphabet, exported.transitions(), exported.init, exported.marked).same_as(oracle)


@pytest.mark.parametrize("option", [["--order", "rcm"], ["--order", "force"], ["--order", "given"],
                                    ["--method", "bfs"], ["--method", "chaining"], ["--reorder"]])
def test_options_do_not_change_the_answer(tmp_path, capsys, option):
    paths, _, _ = small_factory_files(tmp_path, "supcoord")
    code, out, _ = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"],
                           "--json", *option)
    assert code == 0
    payload = json.loads(out)
    assert (payload["states"], payload["transitions"]) == (12, 24)


def test_text_report(tmp_path, capsys):
    paths, _, _ = small_factory_files(tmp_path)
    code, out, _ = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"])
    assert code == 0 and "12 states, 24 transitions" in out


def test_no_spec_means_nonblocking_only(tmp_path, capsys):
    paths, plants, _ = small_factory_files(tmp_path)
    code, out, _ = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--json")
    assert code == 0
    assert json.loads(out)["states"] == X.sync(*plants).n_states == 9


def test_empty_supervisor_is_ok(tmp_path, capsys):
    # the plant can break down uncontrollably into a state the spec forbids from the start
    plant = Generator.from_tct(2, [(0, 10, 1)], 0, [0, 1], "P")
    spec = Generator.from_tct(1, [], 0, [0], "S", extra_events=[10])
    write_generator(plant, tmp_path / "P.gen")
    write_generator(spec, tmp_path / "S.gen")
    code, out, _ = run_cli(capsys, "--plant", tmp_path / "P.gen", "--spec", tmp_path / "S.gen", "--json")
    assert code == 0
    assert json.loads(out) | {"bdd_nodes": 0, "seconds": 0, "effort": None} == {"effort": None,
        "status": "ok", "states": 0, "transitions": 0, "marked": 0, "bdd_nodes": 0, "seconds": 0}


# -- errors: exit 2 with one line, exit 3 on budgets ----------------------------------


def one_line_error(err):
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("supcoord: error:") and "Traceback" not in err
    return lines[0]


def test_missing_file(tmp_path, capsys):
    code, out, err = run_cli(capsys, "--plant", tmp_path / "nope.gen", "--json")
    assert code == 2 and out == ""
    assert "nope.gen" in one_line_error(err)


def test_malformed_file(tmp_path, capsys):
    bad = tmp_path / "bad.gen"
    bad.write_text("<Generator> this is not a generator")
    code, _, err = run_cli(capsys, "--plant", bad)
    assert code == 2 and "bad.gen" in one_line_error(err)


def test_spec_event_unknown_to_plant(tmp_path, capsys):
    paths, _, _ = small_factory_files(tmp_path)
    code, _, err = run_cli(capsys, "--plant", paths["MACH1"], "--spec", paths["BUF"])
    line = one_line_error(err)
    assert code == 2 and "'21'" in line and "BUF.gen" in line and "--spec-only-events selfloop" in line


def test_nondeterministic_file(tmp_path, capsys):
    f = faudes.System()
    a = f.InsControllableEvent("a")
    q0, q1 = f.InsState("x"), f.InsState("y")
    f.SetInitState(q0)
    f.SetTransition(q0, a, q0)
    f.SetTransition(q0, a, q1)
    f.Write(str(tmp_path / "N.gen"))
    code, _, err = run_cli(capsys, "--plant", tmp_path / "N.gen")
    assert code == 2 and "nondeterministic" in one_line_error(err)


def test_empty_plant_alphabet(tmp_path, capsys):
    write_generator(Generator(1, [], [], 0, [0], "EMPTY"), tmp_path / "E.gen")
    code, _, err = run_cli(capsys, "--plant", tmp_path / "E.gen")
    assert code == 2 and "empty alphabet" in one_line_error(err)


@pytest.mark.parametrize("budget", [["--max-nodes", "1"], ["--timeout", "1e-9"]])
def test_budget_gives_unknown(tmp_path, capsys, budget):
    paths, _, _ = small_factory_files(tmp_path)
    code, out, _ = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"],
                           "--json", *budget)
    assert code == 3
    assert json.loads(out)["status"] == "unknown"


def test_bad_budget_value(tmp_path, capsys):
    paths, _, _ = small_factory_files(tmp_path)
    code, _, err = run_cli(capsys, "--plant", paths["MACH1"], "--max-nodes", "0")
    assert code == 2 and "--max-nodes" in one_line_error(err)


# -- random systems through files, against libFAUDES ------------------------------------


@settings(max_examples=25)
@given(systems())
def test_random_systems_agree_with_libfaudes(system):
    _, plants, specs = system
    oracle = faudes_supcon(X.sync(*plants), X.sync(*specs))
    with tempfile.TemporaryDirectory() as d:
        files = []
        for g in plants + specs:
            path = Path(d) / f"{g.name}.gen"
            to_faudes(g).Write(str(path))
            files.append(path)
        out_file = Path(d) / "V.json"
        code = main(["supcon", "--plant", *map(str, files[: len(plants)]), "--spec", *map(str, files[len(plants):]),
                     "--export", str(out_file), "--json", "--quiet"])
        assert code == 0
        payload = json.loads(out_file.read_text())
    assert (payload["states"], len(payload["transitions"]), len(payload["marked"])) == (
        oracle.n_states, oracle.n_transitions, len(oracle.marked))


def test_subprocess(tmp_path):
    paths, _, _ = small_factory_files(tmp_path)
    env = dict(os.environ)
    proc = subprocess.run(
        [sys.executable, "-m", "supcoord.cli", "supcon", "--plant", str(paths["MACH1"]), str(paths["MACH2"]),
         "--spec", str(paths["BUF"]), str(paths["BR"]), "--json"],
        capture_output=True, text=True, env=env, timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    payload = json.loads(proc.stdout)
    assert set(payload) == KEYS | {"effort"} and payload["states"] == 12


def test_export_limit_must_be_positive(tmp_path, capsys):
    path = tmp_path / "G.gen"
    write_generator(Generator(1, [Event("a", True)], [(0, "a", 0)], 0, [0], "G"), path)
    assert main(["supcon", "--plant", str(path), "--spec", str(path), "--export-limit", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--export-limit" in err and "got 0" in err


# -- libFAUDES's conventions: controllability from the plant, specification-only events --------


def plain_generator_file(g: Generator, path: Path) -> Path:
    """``g`` written by libFAUDES as a plain Generator: no controllability flags at all."""
    h = faudes.Generator()
    for e in g.alphabet:
        h.InsEvent(e.name)
    idx = [h.InsState() for _ in range(g.n_states)]
    for a, e, b in g.transitions():
        h.SetTransition(idx[a], h.EventIndex(e), idx[b])
    h.SetInitState(idx[g.init])
    for q in g.marked:
        h.SetMarkedState(idx[q])
    h.Write(str(path))
    return path


@pytest.mark.parametrize("route", ["symbolic", "explicit"])
def test_specifications_without_flags_take_the_plants(tmp_path, capsys, route):
    paths, plants, specs = small_factory_files(tmp_path)
    bare = [plain_generator_file(g, tmp_path / f"plain_{g.name}.gen") for g in specs]
    code, out, err = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", *bare, "--json",
                             "--route", route, "--export", tmp_path / "V.gen")
    assert code == 0 and err == "", err
    assert json.loads(out)["states"] == 12
    exported = from_faudes(faudes.System(str(tmp_path / "V.gen")))
    assert exported.same_as(faudes_supcon(X.sync(*plants), X.sync(*specs)))


def test_a_flag_that_contradicts_the_plant_is_a_warning_naming_event_and_file(tmp_path, capsys):
    paths, _, specs = small_factory_files(tmp_path)
    BUF = specs[0]
    wrong = Generator(BUF.n_states, [Event(e.name, not e.controllable) for e in BUF.alphabet], BUF.transitions(),
                      BUF.init, BUF.marked, "BUF")
    write_generator(wrong, tmp_path / "wrong.gen")
    code, out, err = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", tmp_path / "wrong.gen",
                             paths["BR"], "--json")
    assert code == 0 and json.loads(out)["states"] == 12
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("supcoord: warning: ") and "wrong.gen" in lines[0]
    assert "'10'" in lines[0] and "'21'" in lines[0]


@pytest.mark.parametrize("route", ["symbolic", "explicit"])
def test_specification_only_events_as_controllable_plant_selfloops(tmp_path, capsys, route):
    # the specification counts 'done' events the plant does not have (libFAUDES examples add them
    # to the plant as controllable self-loops)
    paths, plants, specs = small_factory_files(tmp_path)
    BR = specs[1]
    extra = Generator(BR.n_states + 1, BR.alphabet + [Event("done", False)],
                      list(BR.transitions()) + [(0, "done", 2), (2, "done", 0)], 0, [0], "BRX")
    write_generator(extra, tmp_path / "BRX.gen")
    argv = ["--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], tmp_path / "BRX.gen", "--json",
            "--route", route, "--export", tmp_path / "V.gen"]
    code, _, err = run_cli(capsys, *argv)
    assert code == 2 and "'done'" in one_line_error(err) and "BRX.gen" in err
    code, out, err = run_cli(capsys, *argv, "--spec-only-events", "selfloop")
    assert code == 0, err
    G = X.selfloop(X.sync(*plants), [Event("done", True)])
    oracle = faudes_supcon(G, X.sync(specs[0], Generator(extra.n_states, [G.events[e] for e in extra.events],
                                                             extra.transitions(), 0, [0], "BRX")))
    exported = from_faudes(faudes.System(str(tmp_path / "V.gen")))
    assert json.loads(out)["states"] == oracle.n_states and exported.same_as(oracle)


# -- the two routes, the export limit and the export's budget -----------------------------------


@settings(max_examples=15, deadline=None)
@given(systems())
def test_routes_write_the_same_supervisor(system):
    _, plants, specs = system
    with tempfile.TemporaryDirectory() as d:
        files = []
        for g in plants + specs:
            to_faudes(g).Write(str(Path(d) / f"{g.name}.gen"))
            files.append(str(Path(d) / f"{g.name}.gen"))
        texts = []
        for route in ("symbolic", "explicit"):
            out_file = Path(d) / f"V_{route}.gen"
            assert main(["supcon", "--plant", *files[: len(plants)], "--spec", *files[len(plants):], "--route", route,
                         "--export", str(out_file), "--quiet"]) == 0
            texts.append(out_file.read_text())
    assert texts[0] == texts[1]


def test_auto_route_is_explicit_for_a_large_flat_component(tmp_path, capsys):
    n = 700  # a ring of machines' states, more than LARGE_COMPONENT
    ring = Generator.from_tct(n, [(q, 10 + 2 * (q % 2) + (q % 3 == 0), (q + 1) % n) for q in range(n)], 0, [0], "RING")
    write_generator(ring, tmp_path / "RING.gen")
    spec = Generator.from_tct(2, [(0, 11, 1), (1, 12, 0), (0, 10, 0), (1, 10, 1), (0, 13, 0), (1, 13, 1)], 0, [0], "S")
    write_generator(spec, tmp_path / "S.gen")
    results = {}
    for route in ("auto", "symbolic"):
        code, out, err = run_cli(capsys, "--plant", tmp_path / "RING.gen", "--spec", tmp_path / "S.gen", "--json",
                                 "--route", route, "--export", tmp_path / f"V_{route}.gen")
        assert code == 0, err
        results[route] = json.loads(out)
    assert results["auto"]["bdd_nodes"] == 0 and results["symbolic"]["bdd_nodes"] > 0
    assert {k: results["auto"][k] for k in ("states", "transitions", "marked")} == \
        {k: results["symbolic"][k] for k in ("states", "transitions", "marked")}
    assert (tmp_path / "V_auto.gen").read_text() == (tmp_path / "V_symbolic.gen").read_text()


def test_export_limit_is_checked_against_the_known_count_before_any_work(tmp_path, capsys, monkeypatch):
    import supcoord.des.symbolic_export as export

    monkeypatch.setattr(export, "to_flat", lambda *a, **k: pytest.fail("the export was started"))
    paths, _, _ = small_factory_files(tmp_path)
    out_file = tmp_path / "V.gen"
    code, _, err = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"],
                           "--export", out_file, "--export-limit", "11", "--route", "symbolic")
    line = one_line_error(err)
    assert code == 2 and "12 states" in line and "--export-limit 11" in line and not out_file.exists()


def test_a_budget_that_runs_out_in_the_export_names_the_export(tmp_path, capsys, monkeypatch):
    from supcoord.bdd.budget import Budget
    from supcoord.errors import BudgetExceeded

    original = Budget.check

    def check(self, stage, nodes, info):
        if stage == "export":
            raise BudgetExceeded(f"time budget exceeded in {stage}", stats={"stage": stage, **info}, value=1)
        return original(self, stage, nodes, info)

    monkeypatch.setattr(Budget, "check", check)
    paths, _, _ = small_factory_files(tmp_path)
    code, out, _ = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"],
                           "--export", tmp_path / "V.gen", "--json", "--route", "symbolic")
    payload = json.loads(out)
    assert code == 3 and payload["status"] == "unknown" and payload["stats"]["stage"] == "export"
    assert not (tmp_path / "V.gen").exists()


def test_json_effort_reports_stages_and_cudd_counters(tmp_path, capsys):
    """``--json`` of the symbolic route: seconds per fixpoint stage and CUDD's counters."""
    paths, _, _ = small_factory_files(tmp_path, "supcoord")
    code, out, err = run_cli(capsys, "--plant", paths["MACH1"], paths["MACH2"], "--spec", paths["BUF"], paths["BR"],
                             "--json", "--route", "symbolic")
    assert code == 0, err
    effort = json.loads(out)["effort"]
    assert set(effort["stage_seconds"]) == {"product", "reachable", "nonblocking", "controllable", "accessible",
                                            "counts"}
    assert all(t >= 0 for t in effort["stage_seconds"].values())
    assert effort["peak_live_nodes"] >= effort["live_nodes"] > 0
    assert effort["cudd_lookups"] > effort["cudd_hits"] > 0 and effort["cudd_insertions"] > 0
    assert effort["closure_lookups"] >= 0 and effort["closures_abandoned"] >= 0
