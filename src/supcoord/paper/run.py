"""The seed paper's model for ``N`` positioners, end to end: the library behind ``supcoord paper``.

:func:`run_paper` builds ``G = ||_i G^{P_i}`` and ``E = allevents(G) || S`` for an
instance (seeded random starts and targets on the hex grid, or one you give),
synthesizes ``V = supcon(G, E)`` and runs ``CCC(V)``, by one of three routes:

- ``modular`` (literal model only, the default there): exact by Theorems 1 and 2 of
  :mod:`.modular` — each distinct positioner is solved once in a small context,
  ``V`` is the product restricted to ``∏ Z_i``, and a negative CCC verdict comes with a
  certificate naming the positioner whose own supervisor cannot force its target;
- ``settled`` (coupled model, preemptive semantics: its default): CCC on the settled
  states (:mod:`.settled`), without building ``V``; the same verdict, rank and witness
  as the monolithic route, exact by the theorem of that module;
- ``monolithic``: the generic :func:`~supcoord.synthesis.supcon` and
  :func:`~supcoord.synthesis.ccc` on the whole product (for the coupled model, whose
  guards read the neighbours' positions, no component is independent).
  For the coupled model the supervisor is computed without the reachable set
  (``supcon(..., accessible=False)``: same languages, same CCC verdict, rank and witness)
  and CCC runs on it; the exact sizes of the trim supervisor need ``Reach``, the hard
  set of this model, so they are counted (:func:`~supcoord.synthesis.accessible_part`)
  only up to :data:`AUTO_COUNT_COUPLED` positioners unless asked for.

The modular and monolithic routes return the same supervisor (same state-set BDD;
``tests/paper/test_paper.py``); the settled and monolithic routes the same CCC answer
(``tests/paper/test_settled.py``).
:func:`solve_paper` returns the JSON object of ``supcoord paper --json`` (docs/formats.md),
:func:`run_paper` a :class:`PaperRun` that also keeps the generators and results for a
notebook.

>>> r = run_paper(positioners=4, steps=6, seed=2)
>>> r.payload["route"], r.payload["supervisor_states"] == r.supcon.stats["states"], r.payload["ccc"]
('modular', True, False)
>>> r.payload["certificate"].startswith("P1's initial state is not forcible")
True

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (the seed paper).
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, 2019.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..bdd.context import Context
from ..des.symbolic import SymbolicGenerator
from ..errors import InputError
from ..synthesis import CCCResult, SupconResult, accessible_part, ccc, supcon
from ..progress import summary_html, summary_repr
from .coupled import CoupledModel, Geometry, coupled_models
from .literal import PaperInstance, hex_neighbours, hex_sites, literal_models, random_instance
from .modular import literal_modular
from .settled import settled_ccc, target_in_zone

__all__ = ["MODELS", "ROUTES", "AUTO_COUNT_EVENTS", "AUTO_COUNT_COUPLED", "PaperRun", "run_paper", "solve_paper",
           "coupled_instance", "default_route", "json_count", "log10_count"]

MODELS = ("literal", "coupled")
ROUTES = ("modular", "monolithic", "settled")
#: the monolithic route counts transitions exactly only up to this many events (the exact
#: count walks one BDD per event: 20 of 25 s at 100 positioners); the modular route's
#: count is a closed formula and always exact
AUTO_COUNT_EVENTS = 256
#: the coupled model's trim supervisor is counted only up to this many positioners:
#: counting took 5 s at 6 positioners (benchmarks/results/coupled.md), and the reachable
#: set alone 87 s at 7 (coupled_sets.md), where the supervisor without it and CCC take 24 s
AUTO_COUNT_COUPLED = 6
#: longest exact integer put into the JSON (Python's default int/str conversion limit is 4300)
MAX_JSON_DIGITS = 4000


@dataclass
class PaperRun:
    """One run: the instance, ``G``, ``E = allevents(G) || S``, the :class:`SupconResult`,
    the :class:`CCCResult` and the JSON ``payload`` of ``supcoord paper``."""

    instance: PaperInstance
    model: str
    route: str
    G: SymbolicGenerator | None  # None on the settled route, which builds neither G nor V
    E: SymbolicGenerator | None
    supcon: SupconResult | None
    ccc: CCCResult
    payload: dict[str, Any] = field(default_factory=dict)

    @property
    def supervisor(self) -> SymbolicGenerator | None:
        return None if self.supcon is None else self.supcon.supervisor

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: model, route, size, the verdict and the supervisor's numbers."""
        out: dict[str, Any] = {"model": self.model, "route": self.route}
        for key in ("positioners", "steps", "seed"):
            if key in self.payload:
                out[key] = self.payload[key]
        out["forcible"] = getattr(self.ccc, "forcible", None)
        out["rank"] = getattr(self.ccc, "rank", None)
        if self.supcon is not None:
            out.update({k: v for k, v in self.supcon.summary().items() if k in ("states", "marked", "bdd_nodes")})
        return out

    def __repr__(self) -> str:
        return summary_repr("PaperRun", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("PaperRun", self.summary())


def log10_count(count: int | None) -> float | None:
    """``log10(count)`` rounded to 4 decimals (None for None, ``-inf`` never: 0 gives None)."""
    return None if not count else round(math.log10(count), 4)


def json_count(count: int | None) -> int | None:
    """``count`` if it has at most :data:`MAX_JSON_DIGITS` digits, else None (Python 3.11+
    refuses to print or parse longer integers by default, so a 5,000-positioner
    supervisor's ~10^7800 states would make the JSON unreadable; the ``*_log10`` keys
    carry the magnitude)."""
    if count is None or count.bit_length() * 0.30103 < MAX_JSON_DIGITS - 1:
        return count
    return None


def default_route(model: str, semantics: str = "preemptive", count_states: bool | None = None) -> str:
    """``modular`` for the literal model (exact, Theorems 1–2); for the coupled model
    ``settled`` under preemptive semantics (exact, :mod:`.settled`) unless the supervisor's
    states are to be counted, else ``monolithic``.  :func:`run_paper` also takes the
    monolithic route for an instance whose target has an arm in another's safety zone."""
    if model == "literal":
        return "modular"
    return "settled" if semantics == "preemptive" and not count_states else "monolithic"


#: largest model ``run_paper`` builds: positioners (20,000 measured: 97 s and 4 GB for the
#: literal model's modular route at 12 steps) and steps per positioner
MAX_POSITIONERS = 20_000
MAX_STEPS = 4096
MAX_SEED = 2**63 - 1


def _positive_int(value: Any, least: int, flag: str, most: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise InputError(f"must be an integer >= {least}, got {value!r}", value=value, where=flag)
    if most is not None and value > most:
        raise InputError(f"must be at most {most}, got {value!r}", value=value, where=flag)
    return int(value)


def coupled_instance(positioners: int, steps: int, seed: int = 0, geometry: Geometry | None = None,
                     max_tries: int = 2_000, restarts: int = 200) -> PaperInstance:
    """Seeded random starts and targets whose arms are pairwise outside the safety zone,
    priorities = indices, on the first ``positioners`` hex sites.

    Each configuration is found by depth-first search in layout order, positioner ``i``
    trying its positions in a seeded random order against the neighbours already placed
    (the first branch is plain rejection sampling); a search that needs more than
    ``max_tries`` placements restarts with new seeded orders (an unlucky early choice
    can doom a deep subtree), up to ``restarts`` times, then raises :class:`InputError`."""
    seed = _positive_int(seed, 0, "seed")
    rng = np.random.default_rng(seed)
    xy = hex_sites(positioners)
    base = PaperInstance(steps, (0,) * positioners, (0,) * positioners, tuple(range(1, positioners + 1)),
                         hex_neighbours(xy))
    model = CoupledModel(base, geometry)
    confs = []
    for what in ("start", "target"):
        for _ in range(restarts + 1):
            orders = [[int(q) for q in rng.permutation(steps)] for _ in range(positioners)]
            conf = _place(model, orders, max_tries)
            if conf is not None:
                break
        else:
            raise InputError(f"found no {what} configuration of {positioners} positioners with every pair outside "
                             f"the safety zone (seed {seed}, {restarts} restarts of {max_tries} placements)",
                             value=seed, where="seed")
        confs.append(tuple(conf))
    return PaperInstance(steps, confs[0], confs[1], base.priority, base.neighbours)


def _place(model: CoupledModel, orders: list[list[int]], max_tries: int) -> list[int] | None:
    """Depth-first search for a zone-free configuration (explicit stack, no recursion)."""
    size = len(orders)
    conf: list[int] = []
    cursor = [0] * size  # next candidate index of each positioner
    tries = 0
    while len(conf) < size:
        i = len(conf)
        placed = False
        while cursor[i] < len(orders[i]):
            q = orders[i][cursor[i]]
            cursor[i] += 1
            tries += 1
            if not any(model.zone[(i, j)][q, conf[j]] for j in model.neighbours[i] if j < i):
                conf.append(q)
                placed = True
                break
        if not placed:
            if i == 0 or tries > max_tries:
                return None
            cursor[i] = 0
            conf.pop()
    return conf


def run_paper(positioners: int | None = None, steps: int | None = None, model: str = "literal", seed: int = 0,
              semantics: str = "preemptive", ctx: Context | None = None, *, route: str | None = None,
              instance: PaperInstance | None = None, geometry: Geometry | None = None,
              count_transitions: bool | None = None, count_states: bool | None = None) -> PaperRun:
    """Build, synthesize and check the paper's model; see the module docstring.

    ``instance`` replaces the seeded random one (``positioners``/``steps`` are then taken
    from it); ``route`` defaults to :func:`default_route`; ``count_transitions`` (None:
    automatic) asks the monolithic route for the exact transition count even beyond
    :data:`AUTO_COUNT_EVENTS` events; ``count_states`` (None: automatic) asks the coupled
    model for the trim supervisor and its exact sizes even beyond
    :data:`AUTO_COUNT_COUPLED` positioners (``payload["counted"]`` says whether they were
    counted; ``supervisor`` is then the trim one).  A ``ctx`` with a budget makes the run raise
    :class:`~supcoord.errors.BudgetExceeded` when it runs out.
    """
    if model not in MODELS:
        raise InputError(f"must be literal or coupled, got {model!r}", value=model, where="model")
    chosen = route is None
    route = default_route(model, semantics, count_states) if route is None else route
    if route not in ROUTES:
        raise InputError(f"must be modular, monolithic or settled, got {route!r}", value=route, where="route")
    if route == "settled":
        if model != "coupled":
            raise InputError("settled is a route of the coupled model (its collision events settle the levels); "
                             "the literal model's routes are modular and monolithic", value=route, where="route")
        if semantics != "preemptive":
            raise InputError("settled is exact under preemptive semantics only (under standard semantics a "
                             "controllable event may be forced while a collision event is pending); use route "
                             "monolithic", value=semantics, where="semantics")
        if count_states:
            raise InputError("count_states counts V, which the settled route does not build; use route "
                             "monolithic", value=route, where="route")
    if route == "modular" and model != "literal":
        raise InputError("modular is exact for the literal model only (the coupled model's collision "
                         "guards read the neighbours' positions, so its positioners are not independent); "
                         "use route monolithic", value=route, where="route")
    if instance is None:
        positioners = _positive_int(positioners, 1, "positioners", MAX_POSITIONERS)
        steps = _positive_int(steps, 2, "steps", MAX_STEPS)
        seed = _positive_int(seed, 0, "seed", MAX_SEED)
    elif not isinstance(instance, PaperInstance):
        raise InputError(f"instance must be a PaperInstance, got {type(instance).__name__}", value=instance)
    t0 = time.perf_counter()
    counting = 0.0  # seconds spent on the trim supervisor's exact sizes after CCC
    ctx = ctx or Context()
    if model == "literal":
        inst = instance or random_instance(positioners, steps, seed)
    else:
        inst = instance or coupled_instance(positioners, steps, seed, geometry)
    cm = CoupledModel(inst, geometry) if model == "coupled" else None
    if chosen and route == "settled" and target_in_zone(cm) is not None:
        route = "monolithic"  # a collision pending at the target: V may lose it (paper.settled)
    res: SupconResult | None = None
    G = E = None
    if route == "modular":
        G, E, res, c = literal_modular(inst, ctx, semantics)
        t1 = t0 + res.stats["build_seconds"]
        t2 = time.perf_counter() - c.stats.get("seconds", 0.0)
    elif route == "settled":
        c = settled_ccc(cm, ctx)
        t1 = t0 + c.stats["build_seconds"]
        t2 = t1
    else:
        if model == "literal":
            G, E = literal_models(inst, ctx)
        else:
            cm.check()
            G, E = coupled_models(cm, ctx)
        t1 = time.perf_counter()
        count = len(G.events) <= AUTO_COUNT_EVENTS if count_transitions is None else bool(count_transitions)
        whole = model == "coupled"  # the supervisor without Reach (module docstring)
        res = supcon(G, E, count_transitions=count, accessible=not whole)
        t2 = time.perf_counter()
        c = ccc(res.supervisor, semantics, full=False)
        if whole and (inst.size <= AUTO_COUNT_COUPLED if count_states is None else count_states):
            t_count = time.perf_counter()
            res = accessible_part(res, count_transitions=count)
            counting = time.perf_counter() - t_count
    t3 = time.perf_counter()
    sizes = res.stats if res is not None else {"states": None, "transitions": None, "marked": None,
                                                "accessible": False, "bdd_nodes": None}
    payload = {
        "status": "ok",
        "positioners": inst.size,
        "steps": inst.steps,
        "model": model,
        "route": route,
        "seed": seed if instance is None else None,
        "semantics": semantics,
        "supervisor_states": json_count(sizes["states"]),
        "supervisor_states_log10": log10_count(sizes["states"]),
        "supervisor_transitions": json_count(sizes["transitions"]),
        "supervisor_marked": json_count(sizes["marked"]),
        "counted": sizes.get("accessible", True),
        "bdd_nodes": sizes["bdd_nodes"],
        "ccc": c.forcible,
        "rank": c.rank,
        "witness_length": len(c.witness),
        "witness": list(c.witness),
        "certificate": c.stats.get("certificate"),
        "seconds": round(t3 - t0, 4),
        "timings": {"build": round(t1 - t0, 4), "supcon": round(t2 - t1, 4), "ccc": round(t3 - t2 - counting, 4),
                    "count": round(counting, 4), "supcon_iterations": sizes.get("iterations")},
    }
    if route == "modular":
        payload["distinct_components"] = res.stats["distinct_components"]
    if route == "settled":
        payload["settled"] = {k: c.stats[k] for k in ("distance", "buckets", "relations", "max_layer_nodes")}
        payload["settled"]["blocked_group"] = c.stats.get("blocked_group")
    return PaperRun(inst, model, route, G, E, res, c, payload)


def solve_paper(positioners: int | None = None, steps: int | None = None, model: str = "literal", seed: int = 0,
                semantics: str = "preemptive", ctx: Context | None = None, **options: Any) -> dict[str, Any]:
    """The JSON object of ``supcoord paper --json`` (keys: status, positioners, steps,
    model, route, supervisor_states (None beyond 4000 digits), supervisor_states_log10,
    supervisor_transitions, bdd_nodes, ccc, rank,
    witness_length, witness, certificate, seconds, timings); ``options`` as
    :func:`run_paper`."""
    return run_paper(positioners, steps, model, seed, semantics, ctx, **options).payload
