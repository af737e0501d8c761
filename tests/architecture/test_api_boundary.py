"""The library's public boundary: a wrong argument raises the project's own error, naming it.

Every public function and class of ``supcoord.__all__`` is called with arguments of the
wrong type; each call must either succeed or raise a :class:`SupcoordError` subclass (an
``InputError`` naming the parameter), never a raw ``AttributeError``/``TypeError``/numpy
error from deep inside. Then the bad values found by hand.
"""

from __future__ import annotations

import inspect
import math
import warnings

import pytest

import supcoord
from supcoord.errors import InputError, SupcoordError

BAD = [None, "x", 1.5, -1, object(), [], {}, float("nan")]


def _public_callables():
    for name in supcoord.__all__:
        obj = getattr(supcoord, name)
        if callable(obj) and not (inspect.isclass(obj) and issubclass(obj, BaseException)):
            yield name, obj


@pytest.mark.timeout(120)
@pytest.mark.parametrize("name, obj", list(_public_callables()), ids=lambda x: x if isinstance(x, str) else "")
def test_wrong_types_raise_the_projects_errors(name, obj, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a function that writes files (run_demo) writes here
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        pytest.fail(f"{name} has no signature to call it with")
    required = [p for p in sig.parameters.values()
                if p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    raw = []
    for value in BAD:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                obj(*([value] * max(1, len(required))))
            except SupcoordError:
                pass
            except Exception as exc:  # noqa: BLE001 (what this test exists to find)
                raw.append(f"{name}({value!r}): {type(exc).__name__}: {exc}")
    assert not raw, raw


def test_wrong_type_message_names_function_parameter_and_value():
    with pytest.raises(InputError, match=r"solve\(\): problem must be Problem, got str 'p.json'"):
        supcoord.solve("p.json")


def _problem():
    return supcoord.parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [22.4, 0]]},
                                   "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
                                   "collision": {"buffer": 2.0}, "start": [6, 0], "target": [3, 3]})


@pytest.mark.parametrize("call", [
    lambda: supcoord.validate_plan(_problem(), supcoord.Plan("complete", [[[0], [6]]]), resolution=0),
    lambda: supcoord.validate_plan(_problem(), supcoord.Plan("complete", [[[0], [6]]]), resolution=1e-9),
    lambda: supcoord.validate_plan(_problem(), supcoord.Plan("complete", [[[0], [6]]]), resolution=math.inf),
    lambda: supcoord.random_problem([[0, 0], [22.4, 0]], {"kind": "rotary", "arm": 15, "steps": 12}, seed=-1),
    lambda: supcoord.random_problem([[0, 0], [22.4, 0]], {"kind": "rotary", "arm": 15, "steps": 12},
                                    priority="best"),
    lambda: supcoord.Budget(max_nodes=-1),
    lambda: supcoord.Budget(timeout="5"),
    lambda: supcoord.Generator(2, [], [], init=1.5),
    lambda: supcoord.Generator(2, [], [], init=True),
    lambda: supcoord.tct_event(1.7),
    lambda: supcoord.tct_event(True),
    lambda: supcoord.solve(_problem(), improve=math.nan),
    lambda: supcoord.load_problem("no/such/problem.json"),
    lambda: supcoord.read_generator("no/such/g.gen"),
], ids=["resolution-0", "resolution-1e-9", "resolution-inf", "seed--1", "priority", "budget-nodes", "budget-timeout",
        "generator-init-float", "generator-init-bool", "tct-float", "tct-bool", "improve-nan", "missing-problem",
        "missing-generator"])
def test_bad_values_raise_input_errors(call):
    with pytest.raises(SupcoordError):
        call()


def test_plot_with_a_wrong_suffix_is_an_input_error(tmp_path):
    problem = _problem()
    plan = supcoord.solve(problem)
    with pytest.raises(InputError, match="written as"):
        supcoord.save_plan_strip(problem, plan, tmp_path / "x.txt")
    assert not list(tmp_path.iterdir())
