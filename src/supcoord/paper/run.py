"""The seed paper's model for ``N`` positioners, end to end: the library behind ``supcoord paper``.

:func:`run_paper` builds ``G = ||_i G^{P_i}`` and ``E = allevents(G) || S`` for an
instance (seeded random starts and targets on the hex grid, or one you give),
synthesizes ``V = supcon(G, E)`` and runs ``CCC(V)``, by one of three routes (the table
:data:`~supcoord.paper.paper_routes.PAPER_ROUTES` says which runs which model):

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
:func:`run_paper` returns a :class:`PaperRun` (typed: what was built, ``V``'s sizes, the
verdict, the timings) that also keeps the generators and results for a notebook;
:meth:`PaperRun.to_json` makes the JSON object of ``supcoord paper --json``
(docs/formats.md), which :func:`solve_paper` returns.

>>> r = run_paper(positioners=4, steps=6, seed=2)
>>> r.route, r.sizes.states == r.supcon.stats["states"], r.forcible
('modular', True, False)
>>> r.to_json()["certificate"].startswith("P1's initial state is not forcible")
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
from functools import partial
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..bdd.context import Context
from ..des.symbolic import SymbolicGenerator
from ..errors import InputError
from ..synthesis import CCCResult, SupconResult
from ..progress import summary_html, summary_repr
from .coupled import CoupledModel, Geometry
from .literal import PaperInstance, hex_neighbours, hex_sites, random_instance
from .paper_routes import (AUTO_COUNT_COUPLED, AUTO_COUNT_EVENTS, MODELS, ROUTES, RouteOptions, RouteResult, default_route,
                     paper_route)
from .settled import RANK_CPU, RankBounds, target_in_zone

__all__ = ["MODELS", "ROUTES", "AUTO_COUNT_EVENTS", "AUTO_COUNT_COUPLED", "PaperRun", "SupervisorSizes",
           "PaperTimings", "SettledSearch", "run_paper", "solve_paper", "coupled_instance", "default_route",
           "json_count", "log10_count"]

#: longest exact integer put into the JSON (Python's default int/str conversion limit is 4300)
MAX_JSON_DIGITS = 4000


@dataclass(frozen=True)
class SupervisorSizes:
    """The supervisor ``V``'s exact sizes, as far as the route counted them.

    Attributes
    ----------
    states, transitions, marked : int or None
        Exact counts (None where not counted: the settled route builds no ``V``; the
        coupled model's ``V`` without its reachable set is not counted).
    bdd_nodes : int or None
        Nodes of ``V``'s shared BDD (None on the settled route).
    counted : bool
        Whether the sizes are those of the trim supervisor.
    iterations : int or None
        Iterations of supcon's fixpoint.
    """

    states: int | None = None
    transitions: int | None = None
    marked: int | None = None
    bdd_nodes: int | None = None
    counted: bool = False
    iterations: int | None = None

    @classmethod
    def of(cls, result: SupconResult | None) -> SupervisorSizes:
        """The sizes in ``result.stats`` (none for None)."""
        if result is None:
            return cls()
        s = result.stats
        return cls(s["states"], s["transitions"], s["marked"], s["bdd_nodes"], s.get("accessible", True),
                   s.get("iterations"))


@dataclass(frozen=True)
class PaperTimings:
    """Where a run's time went, in seconds: building ``G`` and ``E`` (with the instance),
    synthesizing ``V``, CCC, counting the trim supervisor after CCC; ``total`` is the run."""

    build: float
    supcon: float
    ccc: float
    count: float
    total: float


@dataclass(frozen=True)
class SettledSearch:
    """The settled route's search (:mod:`.settled`): its ``distance`` to the target (None:
    unreachable), Dial ``buckets`` opened, ``relations`` (moves between settled states),
    ``max_layer_nodes`` (BDD nodes of the largest layer), ``blocked_group`` (1-based
    positioners whose own moves cannot reach their targets, or None)."""

    distance: int | None
    buckets: int
    relations: int
    max_layer_nodes: int
    blocked_group: list[int] | None = None

    @classmethod
    def of(cls, c: CCCResult) -> SettledSearch:
        s = c.stats
        return cls(s["distance"], s["buckets"], s["relations"], s["max_layer_nodes"], s.get("blocked_group"))


@dataclass
class PaperRun:
    """One run of :func:`run_paper`: what was built, its sizes, the verdict, the timings.

    Attributes
    ----------
    instance : PaperInstance
        Starts, targets, priorities and neighbours.
    model, route, semantics : str
        The reading of the model, the route taken and the forcibility semantics.
    seed : int or None
        Seed of the random instance (None for an instance given).
    G, E : SymbolicGenerator or None
        The plant and ``allevents(G) || S`` (None on the settled route).
    supcon : SupconResult or None
        The supervisor ``V`` (None on the settled route).
    ccc : CCCResult
        The verdict, rank and witness.
    sizes : SupervisorSizes
        ``V``'s exact sizes, as far as counted.
    timings : PaperTimings
        Seconds per stage.
    distinct_components : int or None
        Modular route: positioners solved (distinct up to symmetry).
    settled : SettledSearch or None
        Settled route: its search.
    rank_bounds : RankBounds or None
        Settled route, when a budget ended the search for the rank after a checked forcing
        string had proved "forcible": ``lower ≤ rank ≤ upper`` (``ccc.rank`` is then None,
        ``ccc.witness`` that string); None when the rank is proved or there is none.

    :meth:`to_json` is the object of ``supcoord paper --json`` (``docs/formats.md``).
    """

    instance: PaperInstance
    model: str
    route: str
    semantics: str
    seed: int | None
    G: SymbolicGenerator | None
    E: SymbolicGenerator | None
    supcon: SupconResult | None
    ccc: CCCResult
    sizes: SupervisorSizes
    timings: PaperTimings
    distinct_components: int | None = None
    settled: SettledSearch | None = None
    rank_bounds: RankBounds | None = None

    @property
    def supervisor(self) -> SymbolicGenerator | None:
        return None if self.supcon is None else self.supcon.supervisor

    @property
    def forcible(self) -> bool:
        """CCC's verdict: whether the target is forcible from the initial state."""
        return self.ccc.forcible

    @property
    def certificate(self) -> str | None:
        """Why not forcible, where a route names a reason (the modular and settled routes)."""
        return self.ccc.stats.get("certificate")

    def to_json(self) -> dict[str, Any]:
        """The JSON object of ``supcoord paper --json``: counts beyond :data:`MAX_JSON_DIGITS`
        digits as null (``*_log10`` carries the magnitude), seconds rounded to 0.1 ms."""
        sizes, t, c = self.sizes, self.timings, self.ccc
        out = {
            "status": "ok", "positioners": self.instance.size, "steps": self.instance.steps, "model": self.model,
            "route": self.route, "seed": self.seed, "semantics": self.semantics,
            "supervisor_states": json_count(sizes.states), "supervisor_states_log10": log10_count(sizes.states),
            "supervisor_transitions": json_count(sizes.transitions), "supervisor_marked": json_count(sizes.marked),
            "counted": sizes.counted, "bdd_nodes": sizes.bdd_nodes, "ccc": c.forcible, "rank": c.rank,
            "witness_length": len(c.witness), "witness": list(c.witness), "certificate": self.certificate,
            "seconds": round(t.total, 4),
            "timings": {"build": round(t.build, 4), "supcon": round(t.supcon, 4), "ccc": round(t.ccc, 4),
                        "count": round(t.count, 4), "supcon_iterations": sizes.iterations},
        }
        if self.distinct_components is not None:
            out["distinct_components"] = self.distinct_components
        if self.settled is not None:
            out["settled"] = dict(vars(self.settled))
        if self.rank_bounds is not None:  # "rank" is null: the bounds say what is proved of it
            b = self.rank_bounds
            out["rank_bounds"] = {"lower": b.lower, "upper": b.upper, "proved": False, "stopped": b.stopped}
        return out

    @property
    def payload(self) -> dict[str, Any]:
        """:meth:`to_json` (the name of earlier releases)."""
        return self.to_json()

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: model, route, size, the verdict and the supervisor's numbers."""
        out: dict[str, Any] = {"model": self.model, "route": self.route, "positioners": self.instance.size,
                               "steps": self.instance.steps, "seed": self.seed,
                               "forcible": self.ccc.forcible, "rank": self.ccc.rank}
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


#: largest model ``run_paper`` builds: positioners (the cost of the largest is in docs/cli.md,
#: ``--positioners``) and steps per positioner
MAX_POSITIONERS = 20_000
MAX_STEPS = 4096
MAX_SEED = 2**63 - 1


def _positive_int(value: Any, least: int, name: str, most: int | None = None) -> int:
    """``value`` as an int in ``[least, most]``, or an :class:`InputError` at the parameter ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise InputError(f"must be an integer >= {least}, got {value!r}", value=value, where=name)
    if most is not None and value > most:
        raise InputError(f"must be at most {most}, got {value!r}", value=value, where=name)
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
              count_transitions: bool | None = None, count_states: bool | None = None,
              rank_cpu: float | None = RANK_CPU) -> PaperRun:
    """Build, synthesize and check the seed paper's model for ``positioners`` positioners.

    Builds ``G`` and ``E = allevents(G) || S`` for a seeded random instance on the hex grid (or
    ``instance``), then ``V = supcon(G, E)`` and ``CCC(V)`` by a route of :data:`.paper_routes.PAPER_ROUTES`.

    Parameters
    ----------
    positioners : int
        Number of positioners, 1 to :data:`MAX_POSITIONERS` (ignored with ``instance``).
    steps : int
        Positions (discrete arm steps) per positioner, 2 to :data:`MAX_STEPS` (ignored with ``instance``).
    model : {"literal", "coupled"}
        The model as printed, or with collision events driven by the arms' geometry.
    seed : int
        Seed of the random starts and targets, >= 0.
    semantics : {"preemptive", "standard"}
        Forcibility semantics of CCC.
    ctx : Context, optional
        The BDD context; with a budget (nodes, seconds) the run stops when it runs out.
    route : {"modular", "monolithic", "settled"}, optional
        None: :func:`~supcoord.paper.paper_routes.default_route` (the coupled model takes the monolithic
        route for an instance whose target has an arm in another's safety zone).
    instance : PaperInstance, optional
        Starts, targets, priorities and neighbours instead of the seeded random ones.
    geometry : Geometry, optional
        The coupled model's arm geometry (mm, degrees); None: the paper's.
    count_transitions : bool, optional
        Monolithic route: exact transition count beyond :data:`AUTO_COUNT_EVENTS` events (None: automatic).
    count_states : bool, optional
        Coupled model: the trim ``V`` and its sizes beyond :data:`AUTO_COUNT_COUPLED` positioners (None: auto).
    rank_cpu : float or None, default :data:`~supcoord.paper.settled.RANK_CPU`
        Settled route: CPU seconds (of this process, from the search's start) the search for
        the rank may take once a checked forcing string has proved "forcible"; past them the
        answer holds the verdict, the string and ``rank_bounds``.  None: no limit.

    Returns
    -------
    PaperRun
        What was built, ``V``'s ``sizes`` (``sizes.counted``: whether counted), the ``ccc``
        verdict, rank and witness, ``timings`` (s); ``to_json()`` is ``supcoord paper --json``.

    Raises
    ------
    InputError
        Unknown model or route, a route not exact here, a size or seed out of range (``where``: the parameter).
    BudgetExceeded
        The budget of ``ctx`` ran out.

    Examples
    --------
    >>> run = run_paper(positioners=4, steps=6, seed=2)
    >>> run.route, run.forcible, run.sizes.states == run.supcon.stats["states"]
    ('modular', False, True)
    >>> run_paper(4, 6, model="coupled", seed=1).route  # CCC on the settled states, no V
    'settled'

    References
    ----------
    .. [1] M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011.
    .. [2] W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer, 2019.
    """
    chosen = route is None
    route = default_route(model, semantics, count_states) if route is None else route
    row = paper_route(model, route, semantics, count_states)
    if instance is None:
        positioners = _positive_int(positioners, 1, "positioners", MAX_POSITIONERS)
        steps = _positive_int(steps, 2, "steps", MAX_STEPS)
        seed = _positive_int(seed, 0, "seed", MAX_SEED)
    elif not isinstance(instance, PaperInstance):
        raise InputError(f"instance must be a PaperInstance, got {type(instance).__name__}", value=instance)
    t0 = time.perf_counter()
    ctx = ctx or Context()
    make = random_instance if model == "literal" else partial(coupled_instance, geometry=geometry)
    inst = instance or make(positioners, steps, seed)
    cm = CoupledModel(inst, geometry) if model == "coupled" else None
    if chosen and route == "settled" and target_in_zone(cm) is not None:
        row = paper_route(model, "monolithic", semantics)  # a collision pending at the target: V may lose it
    done = row.run(inst, cm, ctx, RouteOptions(semantics, count_transitions, count_states, rank_cpu), t0)
    return _paper_run(inst, model, row.route, semantics, None if instance is not None else seed, done, t0)


def _paper_run(inst: PaperInstance, model: str, route: str, semantics: str, seed: int | None, done: RouteResult,
               t0: float) -> PaperRun:
    """The :class:`PaperRun` of a route's result, its timings measured from ``t0`` (s)."""
    t3 = time.perf_counter()
    timings = PaperTimings(build=done.built - t0, supcon=done.synthesized - done.built,
                           ccc=t3 - done.synthesized - done.count_seconds, count=done.count_seconds, total=t3 - t0)
    components = done.supcon.stats["distinct_components"] if route == "modular" else None
    settled = SettledSearch.of(done.ccc) if route == "settled" else None
    return PaperRun(inst, model, route, semantics, seed, done.G, done.E, done.supcon, done.ccc,
                    SupervisorSizes.of(done.supcon), timings, components, settled, done.ccc.stats.get("rank_bounds"))


def solve_paper(positioners: int | None = None, steps: int | None = None, model: str = "literal", seed: int = 0,
                semantics: str = "preemptive", ctx: Context | None = None, **options: Any) -> dict[str, Any]:
    """The JSON object of ``supcoord paper --json``: :meth:`PaperRun.to_json` of
    :func:`run_paper` (keys: status, positioners, steps, model, route, seed, semantics,
    supervisor_states (None beyond 4000 digits), supervisor_states_log10,
    supervisor_transitions, supervisor_marked, counted, bdd_nodes, ccc, rank,
    witness_length, witness, certificate, seconds, timings); ``options`` as
    :func:`run_paper`."""
    return run_paper(positioners, steps, model, seed, semantics, ctx, **options).to_json()
