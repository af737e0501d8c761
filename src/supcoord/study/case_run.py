"""Running one case, in the process that will report it (:mod:`.child` calls it).

:func:`run_case` computes one case of :mod:`.kinds` with the library and returns its
:class:`Measurement`: ``status`` (``ok``, ``timeout``, ``out-of-memory``, ``error``),
``message``, ``seconds`` (the computation alone: no interpreter start, no imports, no
validator), ``bdd_nodes`` (peak live nodes, or the supervisor's node count where the
library reports that), ``states`` (exact, as text, while it has at most 13,000 bits),
``states_log10``, ``verdict``, ``makespan``, ``lower_bound``, ``positioners``, ``size``
and ``extra`` (the kind's other numbers: timings, rank, windows, certificate …).
:meth:`Measurement.to_json` is what the case's process (:mod:`.child`) hands on to the
row of the results database.

Budgets: the case's time limit becomes the library's :class:`~supcoord.bdd.budget.Budget`
timeout, so a long fixpoint stops cleanly between iterations with the statistics so far
(status ``timeout``); its memory limit becomes a node budget (80 % of it at 80 bytes per
node, the command line's rule, ``docs/cli.md``), so a BDD that would not fit stops as
``out-of-memory`` before the hard memory limit (:mod:`.child`) is hit.
"""

from __future__ import annotations

import importlib
import math
import time
from dataclasses import dataclass, field, fields
from typing import Any

from ..errors import BudgetExceeded, SupcoordError

__all__ = ["BYTES_PER_NODE", "Measurement", "outcome_of_exception", "run_case"]

#: bytes per live BDD node assumed for the node budget (supcoord.cli.common.BYTES_PER_NODE)
BYTES_PER_NODE = 80
#: the standard measurement fields a ``call`` function's returned dict may set directly
STANDARD = ("seconds", "bdd_nodes", "states", "states_log10", "verdict", "makespan", "lower_bound", "positioners",
            "size")


@dataclass
class Measurement:
    """What one case measured (the module docstring says each field); None: not measured.

    Attributes
    ----------
    status : str
        ``ok``, ``timeout``, ``out-of-memory`` or ``error`` (a ``call`` function may name its own).
    message : str or None
        Why a case did not end ``ok`` (at most 500 characters).
    seconds : float or None
        The computation alone, in seconds.
    bdd_nodes : int or None
        BDD nodes (the supervisor's, or the peak of live nodes).
    states : str or None
        Exact state count, as decimal text.
    states_log10 : float or None
        ``log10`` of the state count.
    verdict : str or None
        ``forcible``/``not forcible``, ``empty``/``nonempty``, or the planner's status.
    makespan, lower_bound : int or None
        A plan's steps, and the lower bound on them.
    positioners, size : int or None
        The case's x in tables and plots.
    extra : dict
        The kind's other numbers.
    """

    status: str = "ok"
    message: str | None = None
    seconds: float | None = None
    bdd_nodes: int | None = None
    states: str | None = None
    states_log10: float | None = None
    verdict: str | None = None
    makespan: int | None = None
    lower_bound: int | None = None
    positioners: int | None = None
    size: int | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        """The measured fields (None left out) as a JSON object: the case's result file."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}
        if not self.extra:
            del out["extra"]
        return out


def _budget(time_limit: float | None, memory_limit_mb: float | None):
    from ..bdd.budget import Budget

    nodes = None if memory_limit_mb is None else max(1000, int(memory_limit_mb * 2**20 * 0.8 / BYTES_PER_NODE))
    return Budget(max_nodes=nodes, timeout=time_limit)


def _count(states: int | None) -> dict[str, Any]:
    """``states`` and ``states_log10`` of a :class:`Measurement` (text while under 13,000 bits)."""
    if states is None:
        return {}
    log10 = _log10(states) if states > 0 else None
    return {"states": str(states) if states.bit_length() < 13_000 else None, "states_log10": log10}


def _log10(n: int) -> float:
    """log10 of an integer of any size (float conversion overflows past 10^308)."""
    shift = max(0, n.bit_length() - 60)
    return math.log10(n >> shift) + shift * math.log10(2)


def run_case(kind: str, params: dict[str, Any], time_limit: float | None = None,
             memory_limit_mb: float | None = None) -> Measurement:
    """The measurement of one case (module docstring); library errors become a status."""
    budget = _budget(time_limit, memory_limit_mb)
    try:
        return {"paper": _paper, "solve": _solve, "supcon": _supcon, "force": _force, "call": _call}[kind](params, budget)
    except BaseException as exc:
        outcome = outcome_of_exception(exc)
        if outcome is None:
            raise
        return outcome


def outcome_of_exception(exc: BaseException) -> Measurement | None:
    """The measurement of a case that ended with ``exc`` (None: re-raise it)."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, BudgetExceeded):
        stats = exc.stats
        status = "out-of-memory" if text.startswith("node budget") else "timeout"
        return Measurement(status, text[:500], seconds=stats.get("seconds"), bdd_nodes=stats.get("bdd_nodes"),
                           extra={"stage": stats.get("stage")})
    if isinstance(exc, MemoryError) or (isinstance(exc, (RuntimeError, ValueError)) and (
            "out of memory" in text.lower() or "`NULL` pointer" in text)):
        return Measurement("out-of-memory", f"{type(exc).__name__}: {text}"[:500])
    if isinstance(exc, SupcoordError):
        return Measurement("error", exc.one_line()[:500])
    return None


# -- the kinds ----------------------------------------------------------------------------------


def _paper(p: dict[str, Any], budget) -> Measurement:
    """The paper's model by the case's route.  What is measured follows what the route
    builds: the modular and monolithic routes synthesize ``V`` (``bdd_nodes`` is its node
    count; its states are recorded where the route counted them, ``sizes.counted``);
    the settled route builds no ``V`` (``bdd_nodes`` is the peak of live nodes of its
    search, no states; its search's numbers are in ``extra["settled"]``)."""
    from ..bdd.context import Context
    from ..paper.run import run_paper

    ctx = Context(budget=budget)
    t0 = time.perf_counter()
    run = run_paper(p["positioners"], p["steps"], p["model"], p["seed"], p["semantics"], ctx, route=p["route"],
                    count_transitions=p["count_transitions"])
    seconds = time.perf_counter() - t0
    pay = run.to_json()  # the extra numbers as supcoord paper --json has them
    extra = {k: pay.get(k) for k in ("route", "rank", "witness_length", "certificate", "timings",
                                     "distinct_components", "settled", "counted")}
    extra["peak_nodes"] = ctx.peak_nodes()
    extra["supervisor_transitions"] = None if pay.get("supervisor_transitions") is None else str(pay["supervisor_transitions"])
    counted = run.supcon is not None and run.sizes.counted
    nodes = run.sizes.bdd_nodes if run.supcon is not None else ctx.peak_nodes()
    n = run.instance.size
    return Measurement(seconds=seconds, bdd_nodes=nodes, **_count(run.sizes.states if counted else None),
                       verdict="forcible" if run.forcible else "not forcible", positioners=n, size=n, extra=extra)


def problem_of(p: dict[str, Any]):
    """The :class:`~supcoord.problems.problem.Problem` of a ``solve`` case."""
    if p["problem"] == "random":
        from ..problems.random import random_problem

        layout = dict(p["layout"] or {"kind": "hex", "pitch": 22.4})
        if p["rings"] is not None:
            layout["rings"] = p["rings"]
        return random_problem(layout, p["kinematics"], 2.0 if p["buffer"] is None else p["buffer"], p["seed"],
                              priority=p["priority"])
    if p["problem"] == "preset":
        from ..problems.presets import preset_problem

        options = {k: p[k] for k in ("alpha_steps", "beta_steps", "buffer", "start") if p[k] is not None}
        return preset_problem(p["instrument"], 2 if p["rings"] is None else p["rings"], p["seed"],
                              priority=p["priority"], **options)
    from ..problems.problem import load_problem

    return load_problem(p["problem"])


def _solve(p: dict[str, Any], budget) -> Measurement:
    from ..planning.planner import solve
    from ..planning.routes import route_named
    from ..problems.validate import validate_plan

    problem = problem_of(p)
    t0 = time.perf_counter()
    try:
        plan = solve(problem, route_named(p["route"], p["order"]), budget=budget, validation="none",
                     improve=p["improve"])
    except BudgetExceeded as exc:
        out = outcome_of_exception(exc)
        out.extra.update({k: exc.stats.get(k) for k in ("windows", "largest_window")})
        out.positioners = out.size = problem.n
        return out
    seconds = time.perf_counter() - t0
    s = plan.stats
    extra = {k: s.get(k) for k in ("windows", "largest_window", "single_moves", "schedule", "improve_seconds")}
    out = Measurement(seconds=seconds, bdd_nodes=s.get("bdd_nodes"), verdict=plan.status, positioners=problem.n,
                      size=problem.n, lower_bound=plan.lower_bound, extra=extra)
    if plan.status == "complete":
        out.makespan = plan.makespan
        if p["validate"]:
            t1 = time.perf_counter()
            result = validate_plan(problem, plan)
            extra.update(valid=result.valid, validate_seconds=time.perf_counter() - t1)
            if not result.valid:
                out.status, out.message = "error", f"the plan fails validation: {result.problems[:2]}"
    else:
        extra["certificate"] = s.get("certificate")
        out.message = plan.reason[:500]
    return out


def _family(ctx, family: str, size: int, method: str = "saturation"):
    from ..des import families, symbolic_ops
    from ..synthesis.supcon import lift_spec, supcon

    plants, specs = families.FAMILIES[family](size)
    G, E = families.to_symbolic(ctx, plants, specs)
    E = lift_spec(G, E) if E is not None else symbolic_ops.allevents(ctx, G)
    return supcon(G, E, method=method)


def _supcon(p: dict[str, Any], budget) -> Measurement:
    from ..bdd.context import Context

    ctx = Context(budget=budget)
    t0 = time.perf_counter()
    res = _family(ctx, p["family"], p["size"], p["method"])
    seconds = time.perf_counter() - t0
    st = res.stats
    return Measurement(seconds=seconds, bdd_nodes=st["bdd_nodes"], **_count(st["states"]), size=p["size"],
                       verdict="empty" if st["states"] == 0 else "nonempty",
                       extra={"transitions": str(st["transitions"]), "iterations": st.get("iterations")})


def _force(p: dict[str, Any], budget) -> Measurement:
    from ..bdd.context import Context
    from ..synthesis.ccc import ccc

    ctx = Context(budget=budget)
    t0 = time.perf_counter()
    if p["family"] is not None:
        V = _family(ctx, p["family"], p["size"]).supervisor
        target = None
    else:
        from ..des.io import read_generator
        from ..des.symbolic import from_explicit

        g = read_generator(p["generator"])
        V = from_explicit(ctx, g, "q")
        target = None if p["target"] == "marked" else V.state_of({"q": _state(g, p["target"])})
    t1 = time.perf_counter()
    c = ccc(V, p["semantics"], target=target)
    t2 = time.perf_counter()
    return Measurement(seconds=t2 - t1, bdd_nodes=c.stats.get("bdd_nodes"), **_count(V.count_states()),
                       size=p["size"], verdict="forcible" if c.forcible else "not forcible",
                       extra={"rank": c.rank, "layers": len(c.layers), "setup_seconds": t1 - t0,
                              "witness_length": len(c.witness)})


def _state(g, text: str) -> int:
    from ..errors import InputError

    if g.state_names is not None and text in g.state_names:
        return g.state_names.index(text)
    if text.isdigit() and int(text) < g.n_states:
        return int(text)
    raise InputError(f"unknown state {text!r}", value=text, where="target")


def _accepts(func, name: str) -> bool:
    import inspect

    try:
        params = inspect.signature(func).parameters
    except (TypeError, ValueError):  # builtins without a signature
        return False
    return name in params or any(q.kind is inspect.Parameter.VAR_KEYWORD for q in params.values())


def _call(p: dict[str, Any], budget) -> Measurement:
    module, name = p["function"].split(":")
    try:
        func = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as exc:
        from ..errors import InputError

        raise InputError(f"cannot import {p['function']!r}: {exc}", value=p["function"], where="function") from None
    kwargs = dict(p["kwargs"])
    for name in ("size", "positioners"):  # handed to a function that takes them (a grid axis of the block)
        if p[name] is not None and name not in kwargs and _accepts(func, name):
            kwargs[name] = p[name]
    t0 = time.perf_counter()
    value = func(*p["args"], **kwargs)
    out = Measurement(seconds=time.perf_counter() - t0, size=p["size"], positioners=p["positioners"])
    if isinstance(value, dict):
        for name in STANDARD:
            if name in value:
                setattr(out, name, value[name])
        if "status" in value:
            out.status = str(value["status"])
        out.extra = {k: v for k, v in value.items() if k not in STANDARD and k != "status"}
    elif value is not None:
        out.extra = {"result": repr(value)[:500]}
    return out
