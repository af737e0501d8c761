"""The paper's routes as one table, read by run_paper and the study; typed results; library
errors that name parameters, told as options by the command line."""

from __future__ import annotations

import itertools
import subprocess
import sys

import pytest

from supcoord.errors import InputError
from supcoord.paper.paper_routes import MODELS, PAPER_ROUTES, ROUTES, SEMANTICS, default_route, paper_route, route_rule
from supcoord.study.case_run import Measurement
from supcoord.study.kinds import check_params

COMBINATIONS = list(itertools.product(MODELS, ROUTES, SEMANTICS))


@pytest.mark.parametrize("model, route, semantics", COMBINATIONS, ids=str)
def test_the_study_and_run_paper_accept_the_same_routes(model, route, semantics):
    """A study's paper case is refused exactly when run_paper would refuse the route."""
    try:
        paper_route(model, route, semantics)
        library = True
    except InputError as exc:
        assert exc.where in ("route", "semantics")
        library = False
    params = {"positioners": 2, "steps": 6, "model": model, "route": route, "semantics": semantics}
    try:
        check_params("paper", params, "cases[0]")
        study = True
    except InputError as exc:
        assert exc.where == "cases[0].route" and str(exc).endswith("use route = 'monolithic'")
        study = False
    assert library == study == (route_rule(model, route, semantics) is None)


def test_every_model_has_its_default_route_in_the_table():
    rows = {(r.model, r.route) for r in PAPER_ROUTES}
    assert all((m, default_route(m, s)) in rows for m in MODELS for s in SEMANTICS)
    assert paper_route("coupled", "monolithic").builds_supervisor and not paper_route("coupled", "settled").builds_supervisor
    with pytest.raises(InputError) as err:
        paper_route("coupled", "settled", count_states=True)
    assert err.value.where == "route" and "count_states" in err.value.message


def test_run_paper_returns_typed_results_and_json_made_from_them():
    from supcoord.paper.run import PaperTimings, SupervisorSizes, run_paper

    run = run_paper(3, 6, seed=1)
    assert isinstance(run.sizes, SupervisorSizes) and isinstance(run.timings, PaperTimings)
    assert run.sizes.counted and run.sizes.states == run.supervisor.count_states() and run.settled is None
    js = run.to_json()
    assert list(js) == ["status", "positioners", "steps", "model", "route", "seed", "semantics", "supervisor_states",
                        "supervisor_states_log10", "supervisor_transitions", "supervisor_marked", "counted",
                        "bdd_nodes", "ccc", "rank", "witness_length", "witness", "certificate", "seconds", "timings",
                        "distinct_components"]
    assert (js["ccc"], js["rank"], js["witness"], js["supervisor_states"]) == (
        run.forcible, run.ccc.rank, run.ccc.witness, run.sizes.states)
    settled = run_paper(3, 6, model="coupled", seed=1)
    assert settled.route == "settled" and settled.sizes == SupervisorSizes() and settled.settled.relations > 0
    assert settled.to_json()["settled"] == vars(settled.settled) and "distinct_components" not in settled.to_json()


def test_a_measurement_leaves_out_what_was_not_measured():
    assert Measurement().to_json() == {"status": "ok"}
    m = Measurement(seconds=1.5, states="12", extra={"rank": 2})
    assert m.to_json() == {"status": "ok", "seconds": 1.5, "states": "12", "extra": {"rank": 2}}


def test_library_errors_name_parameters_and_the_command_line_its_options(tmp_path):
    from supcoord.cli.common import as_option_error
    from supcoord.study import run_study, study_from_dict

    study = study_from_dict({"cases": [{"kind": "call", "function": "math:sqrt", "args": [4]}]})
    for kwargs, where in (({"workers": -1}, "workers"), ({"workers": 0, "retry": ["ok"]}, "retry")):
        with pytest.raises(InputError) as err:
            run_study(study, tmp_path / "r.sqlite", progress=None, **kwargs)
        assert err.value.where == where and "--" not in err.value.one_line()
    told = as_option_error(InputError("needs dask; or use workers=0", where="workers"), {"workers": "--workers"})
    assert told.one_line() == "--workers: needs dask; or use --workers 0"
    other = InputError("bad", where="study.toml: cases[0].workers")
    assert as_option_error(other, {"workers": "--workers"}) is other


def test_the_command_line_tells_the_library_errors_with_its_options(tmp_path, capsys):
    from supcoord.cli.main import main

    (tmp_path / "s.toml").write_text('[[cases]]\nkind = "call"\nfunction = "math:sqrt"\n')
    runs = {
        ("paper", "--positioners", "3", "--steps", "6", "--route", "settled"): "--route: settled is a route of",
        ("paper", "--positioners", "3", "--steps", "6", "--model", "coupled", "--route", "settled",
         "--count-states"): "--route: --count-states counts V, which the settled route does not build; use --route",
        ("study", "run", str(tmp_path / "s.toml"), "--workers", "-1"): "--workers: must be >= 0, got -1",
    }
    for args, expected in runs.items():
        code = main(list(args))
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and expected in err, err


def test_reading_a_study_of_paper_cases_imports_no_bdd_package():
    code = ("import sys; from supcoord.study import study_from_dict; "
            "study_from_dict({'cases': [{'kind': 'paper', 'steps': 6, 'positioners': 2, 'model': 'coupled'}]}); "
            "heavy = [m for m in ('dd', 'numpy', 'supcoord.bdd', 'supcoord.paper.run') if m in sys.modules]; "
            "assert not heavy, heavy")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)
