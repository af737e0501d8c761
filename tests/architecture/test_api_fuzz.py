"""Public-API fuzz: every public function and class of ``supcoord`` fed malformed values.

For every name of ``supcoord.__all__`` that can be called (a new public function is
covered without editing this file), hypothesis draws arguments from a pool of hostile
values — wrong types, NaN and infinities, huge and negative integers, empty and huge
strings, impossible file names, containers of junk — and from problems and plans that
were valid and then had one field replaced.  Each call must succeed or raise a
:class:`~supcoord.errors.SupcoordError` within :data:`CALL_SECONDS` (an interval timer
interrupts a hang, which fails the test).  Derandomized: CI sees the same examples.
"""

from __future__ import annotations

import copy
import inspect
import math
import signal
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import supcoord
from supcoord.errors import SupcoordError

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"

#: seconds one call may take: far more than a malformed value needs to be refused
CALL_SECONDS = 10.0
#: examples per public name (about 70 names; the whole file well under a minute)
PER_NAME = 12

#: public names not fuzzed, and why (each must stay justified)
SKIPPED: dict[str, str] = {}

JUNK = [None, "", "x" * 5000, "no/such/file.json", "a\0b", math.nan, math.inf, -math.inf, -1, 0, 1, 10**100,
        -10**100, True, 1.5, [], {}, (), [[1, 2]], {"kind": []}, object(), b"\xff\x00", np.array([np.nan]),
        np.zeros((0, 3)), [None] * 3, "²", "٣", {"1": [0, 180], "01": [0, 180]}]


class Hang(Exception):
    """Raised by the interval timer inside a call that took longer than CALL_SECONDS."""


def _alarm(signum, frame):  # noqa: ARG001
    raise Hang(f"no answer within {CALL_SECONDS} s")


_CACHE: dict[str, object] = {}


def _problem():
    if "problem" not in _CACHE:
        _CACHE["problem"] = supcoord.load_problem(EXAMPLES / "three_rotary.json")
    return copy.deepcopy(_CACHE["problem"])


def _plan():
    if "plan" not in _CACHE:
        _CACHE["plan"] = supcoord.solve(_problem())
    return copy.deepcopy(_CACHE["plan"])


PROBLEM_MUTATIONS = {
    "target float": lambda p: p.target.astype(float) + 0.5,
    "target list": lambda p: p.target.tolist(),
    "start out of range": lambda p: np.full_like(p.start, 99),
    "start negative": lambda p: np.full_like(p.start, -1),
    "buffers nan": lambda p: np.full(p.n, np.nan),
    "bases short": lambda p: p.bases[:1].copy(),
    "priority None": lambda p: None,
    "kinematics None": lambda p: None,
    "held junk": lambda p: {"x": 1},
    "obstacles nan": lambda p: np.full((1, 2, 2), np.nan),
}
PLAN_MUTATIONS = {
    "configurations float": lambda p: [np.full((3, 1), 1.5)],
    "configurations huge": lambda p: [np.full((3, 1), 10**30, dtype=object)],
    "configurations str": lambda p: ["abc"],
    "configurations None": lambda p: None,
    "configurations other shape": lambda p: [np.zeros((19, 1), dtype=np.int64)],
    "angles nan": lambda p: [np.full((3, 1), np.nan)],
    "status int": lambda p: 3,
    "lattice junk": lambda p: (0, -1),
    "makespan str": lambda p: "x",
    "trajectories junk": lambda p: [{"theta": "x"}],
}
_FIELD = {"target float": "target", "target list": "target", "start out of range": "start", "start negative": "start",
          "buffers nan": "buffers", "bases short": "bases", "priority None": "priority", "kinematics None": "kinematics",
          "held junk": "held", "obstacles nan": "obstacles"}
_PLAN_FIELD = {k: k.split()[0].replace("angles", "angles_deg") for k in PLAN_MUTATIONS}


def _mutated_problem(name: str):
    p = _problem()
    object.__setattr__(p, _FIELD[name], PROBLEM_MUTATIONS[name](p))
    return p


def _mutated_plan(name: str):
    plan = _plan()
    setattr(plan, _PLAN_FIELD[name], PLAN_MUTATIONS[name](plan))
    return plan


hostile = st.one_of(
    st.sampled_from(JUNK),
    st.sampled_from(sorted(PROBLEM_MUTATIONS)).map(_mutated_problem),
    st.sampled_from(sorted(PLAN_MUTATIONS)).map(_mutated_plan),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
)


def _public_callables():
    for name in sorted(supcoord.__all__):
        obj = getattr(supcoord, name)
        if callable(obj) and not (inspect.isclass(obj) and issubclass(obj, BaseException)):
            yield name


@pytest.mark.timeout(120)
@pytest.mark.parametrize("name", [n for n in _public_callables() if n not in SKIPPED])
def test_public_api_answers_malformed_values_with_its_own_errors(name, tmp_path, monkeypatch):
    obj = getattr(supcoord, name)
    monkeypatch.chdir(tmp_path)  # a function that writes files (run_demo) writes here
    params = list(inspect.signature(obj).parameters.values())
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    keywords = [p.name for p in params if p.kind is p.KEYWORD_ONLY]

    @settings(max_examples=PER_NAME, derandomize=True, deadline=None, database=None,
              suppress_health_check=list(HealthCheck))
    @given(data=st.data())
    def fuzz(data):
        required = [p for p in positional if p.default is p.empty]
        count = data.draw(st.integers(len(required), max(len(required), min(len(positional), len(required) + 2))),
                          label="positional count")
        args = [data.draw(hostile, label=positional[i].name) for i in range(count)]
        kwargs = {}
        if keywords and data.draw(st.booleans(), label="a keyword"):
            key = data.draw(st.sampled_from(keywords), label="keyword")
            kwargs[key] = data.draw(hostile, label=key)
        assume(args or kwargs)  # a call with the defaults only is a valid call (run_demo: the whole demo)
        old = signal.signal(signal.SIGALRM, _alarm)
        signal.setitimer(signal.ITIMER_REAL, CALL_SECONDS)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                obj(*args, **kwargs)
        except SupcoordError:
            pass
        except Hang:
            pytest.fail(f"{name}(*{args!r:.300}, **{kwargs!r:.200}) did not answer within {CALL_SECONDS} s")
        except Exception as exc:  # noqa: BLE001 (what this test exists to find)
            pytest.fail(f"{name}(*{args!r:.300}, **{kwargs!r:.200}) raised {type(exc).__name__}: {exc!s:.300}")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)
        import matplotlib.pyplot as plt

        plt.close("all")

    fuzz()
