"""The routes of the seed paper's model: one table of which route runs which model, how.

A *route* is one way to compute ``V = supcon(G, allevents(G) || S)`` and ``CCC(V)`` (or
CCC's answer alone) for an instance of the paper's model.  :data:`PAPER_ROUTES` has one
row per (model, route): the semantics under which the route is exact, whether it builds
``V`` (so that its states can be counted), and the function that runs it.

===========  ============  ======================  ========  =========================================
model        route         semantics (exact)       builds V  function
===========  ============  ======================  ========  =========================================
literal      modular       preemptive, standard    yes       :func:`.modular.literal_modular`
literal      monolithic    preemptive, standard    yes       :func:`~supcoord.synthesis.supcon`, ``ccc``
coupled      monolithic    preemptive, standard    yes       the same, ``V`` without its reachable set
coupled      settled       preemptive              no        :func:`.settled.settled_ccc`
===========  ============  ======================  ========  =========================================

:func:`paper_route` checks a request against the table (the library's errors name the
parameter: ``route``, ``semantics``); :func:`route_rule` says the same in one short
sentence for a study file; :func:`default_route` is the route taken when none is named.
:func:`~supcoord.paper.run.run_paper` and the study's ``paper`` cases
(:mod:`supcoord.study.kinds`) both read the table.  This module imports no BDD package
(the route functions import theirs when they run), so reading a study stays light.

>>> paper_route("literal", "modular").semantics
('preemptive', 'standard')
>>> [r.route for r in PAPER_ROUTES if r.model == "coupled"]
['monolithic', 'settled']
>>> route_rule("coupled", "modular", "preemptive")
'modular is exact for the literal model only'

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011.
- ``docs/paper.md``: Theorems 1 and 2 (the modular route), the settled states.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:
    from ..bdd.context import Context
    from ..des.symbolic import SymbolicGenerator
    from ..synthesis import CCCResult, SupconResult
    from .coupled import CoupledModel
    from .literal import PaperInstance

__all__ = ["MODELS", "ROUTES", "SEMANTICS", "AUTO_COUNT_EVENTS", "AUTO_COUNT_COUPLED", "PAPER_ROUTES", "PaperRoute",
           "RouteOptions", "RouteResult", "default_route", "paper_route", "route_rule"]

MODELS = ("literal", "coupled")
ROUTES = ("modular", "monolithic", "settled")
SEMANTICS = ("preemptive", "standard")
#: the monolithic route counts transitions exactly only up to this many events (the exact
#: count walks one BDD per event); the modular route's count is a closed formula and always exact
AUTO_COUNT_EVENTS = 256
#: the coupled model's trim supervisor is counted only up to this many positioners (its
#: reachable set, which the counts need, costs more than synthesis and CCC together beyond;
#: measurements in benchmarks/results/coupled.md)
AUTO_COUNT_COUPLED = 6


@dataclass(frozen=True)
class RouteOptions:
    """What a route may be asked besides the instance.

    Attributes
    ----------
    semantics : str
        Forcibility semantics of CCC, ``"preemptive"`` or ``"standard"``.
    count_transitions : bool or None
        Monolithic route: count the supervisor's transitions exactly (None: up to
        :data:`AUTO_COUNT_EVENTS` events).
    count_states : bool or None
        Coupled model, monolithic route: build the trim supervisor and count its states
        (None: up to :data:`AUTO_COUNT_COUPLED` positioners).
    rank_cpu : float or None
        Settled route: CPU seconds the search for the rank may take once a checked forcing
        string has proved "forcible" (None: no limit); :func:`~supcoord.paper.run.run_paper`
        passes :data:`~supcoord.paper.settled.RANK_CPU` unless told otherwise.
    """

    semantics: str = "preemptive"
    count_transitions: bool | None = None
    count_states: bool | None = None
    rank_cpu: float | None = None


@dataclass
class RouteResult:
    """What a route built and decided, with the moments its stages ended.

    Attributes
    ----------
    G, E : SymbolicGenerator or None
        The plant and the specification (None on the settled route, which builds neither).
    supcon : SupconResult or None
        The supervisor ``V`` and its sizes (None on the settled route).
    ccc : CCCResult
        The verdict, rank and witness.
    built, synthesized : float
        ``time.perf_counter()`` (s) when the model was built and when ``V`` was synthesized.
    count_seconds : float
        Seconds spent counting the trim supervisor's exact sizes after CCC.
    """

    G: SymbolicGenerator | None
    E: SymbolicGenerator | None
    supcon: SupconResult | None
    ccc: CCCResult
    built: float
    synthesized: float
    count_seconds: float = 0.0


#: a route's function: (instance, coupled model or None, context, options, start of the run (s)) -> result
RouteFunction = Callable[["PaperInstance", "CoupledModel | None", "Context", RouteOptions, float], RouteResult]


def _modular(inst: PaperInstance, cm: CoupledModel | None, ctx: Context, options: RouteOptions,
             start: float) -> RouteResult:
    """Theorems 1 and 2: each distinct positioner solved once (:mod:`.modular`)."""
    from .modular import literal_modular

    G, E, res, c = literal_modular(inst, ctx, options.semantics)
    return RouteResult(G, E, res, c, start + res.stats["build_seconds"],
                       time.perf_counter() - c.stats.get("seconds", 0.0))


def _settled(inst: PaperInstance, cm: CoupledModel | None, ctx: Context, options: RouteOptions,
             start: float) -> RouteResult:
    """CCC on the coupled model's settled states, without ``V`` (:mod:`.settled`)."""
    from .settled import settled_ccc

    c = settled_ccc(cm, ctx, rank_cpu=options.rank_cpu)
    built = start + c.stats["build_seconds"]
    return RouteResult(None, None, None, c, built, built)


def _literal_monolithic(inst: PaperInstance, cm: CoupledModel | None, ctx: Context, options: RouteOptions,
                        start: float) -> RouteResult:
    """The generic supcon and CCC on the literal model's whole product."""
    from .literal import literal_models

    G, E = literal_models(inst, ctx)
    return _monolithic(G, E, options, trim=True)


def _coupled_monolithic(inst: PaperInstance, cm: CoupledModel | None, ctx: Context, options: RouteOptions,
                        start: float) -> RouteResult:
    """The generic supcon and CCC on the coupled model, ``V`` computed without ``Reach``
    (same languages, verdict, rank and witness); its exact sizes counted only when asked
    or up to :data:`AUTO_COUNT_COUPLED` positioners."""
    from .coupled import coupled_models

    cm.check()
    G, E = coupled_models(cm, ctx)
    count = inst.size <= AUTO_COUNT_COUPLED if options.count_states is None else bool(options.count_states)
    return _monolithic(G, E, options, trim=False, count_states=count)


def _monolithic(G: SymbolicGenerator, E: SymbolicGenerator, options: RouteOptions, trim: bool,
                count_states: bool = False) -> RouteResult:
    from ..synthesis import accessible_part, ccc, supcon

    built = time.perf_counter()
    count = len(G.events) <= AUTO_COUNT_EVENTS if options.count_transitions is None else bool(options.count_transitions)
    res = supcon(G, E, count_transitions=count, accessible=trim)
    synthesized = time.perf_counter()
    c = ccc(res.supervisor, options.semantics, full=False)
    counting = 0.0
    if not trim and count_states:
        t_count = time.perf_counter()
        res = accessible_part(res, count_transitions=count)
        counting = time.perf_counter() - t_count
    return RouteResult(G, E, res, c, built, synthesized, counting)


@dataclass(frozen=True)
class PaperRoute:
    """One row of :data:`PAPER_ROUTES`.

    Attributes
    ----------
    model : str
        ``"literal"`` or ``"coupled"``.
    route : str
        ``"modular"``, ``"monolithic"`` or ``"settled"``.
    semantics : tuple of str
        The semantics under which the route's answer is exact.
    builds_supervisor : bool
        Whether the route builds ``V`` (so that its states can be counted).
    run : callable
        ``run(instance, coupled_model, ctx, options, start) -> RouteResult``.
    """

    model: str
    route: str
    semantics: tuple[str, ...]
    builds_supervisor: bool
    run: RouteFunction


PAPER_ROUTES: tuple[PaperRoute, ...] = (
    PaperRoute("literal", "modular", SEMANTICS, True, _modular),
    PaperRoute("literal", "monolithic", SEMANTICS, True, _literal_monolithic),
    PaperRoute("coupled", "monolithic", SEMANTICS, True, _coupled_monolithic),
    PaperRoute("coupled", "settled", ("preemptive",), False, _settled),
)
_TABLE = {(r.model, r.route): r for r in PAPER_ROUTES}

#: why a route refuses a model, and (settled) a semantics or a count of ``V``'s states
_WRONG_MODEL = {
    "modular": "modular is exact for the literal model only (the coupled model's collision guards read the "
               "neighbours' positions, so its positioners are not independent); use route monolithic",
    "settled": "settled is a route of the coupled model (its collision events settle the levels); the literal "
               "model's routes are modular and monolithic",
}
_WRONG_SEMANTICS = ("settled is exact under preemptive semantics only (under standard semantics a controllable "
                    "event may be forced while a collision event is pending); use route monolithic")
_NO_SUPERVISOR = "count_states counts V, which the settled route does not build; use route monolithic"
#: the same rules in one short sentence each (a study file's messages)
_RULES = {"modular": "modular is exact for the literal model only",
          "settled": "settled is a route of the coupled model under preemptive semantics"}


def default_route(model: str, semantics: str = "preemptive", count_states: bool | None = None) -> str:
    """The route taken when none is named.

    Parameters
    ----------
    model : str
        ``"literal"`` or ``"coupled"``.
    semantics : str
        ``"preemptive"`` or ``"standard"``.
    count_states : bool or None
        Whether the supervisor's states are to be counted (then a route that builds ``V``).

    Returns
    -------
    str
        ``modular`` for the literal model (exact, Theorems 1–2); for the coupled model
        ``settled`` under preemptive semantics unless the states are to be counted, else
        ``monolithic``.  :func:`~supcoord.paper.run.run_paper` also takes the monolithic
        route for an instance whose target has an arm in another's safety zone.

    Examples
    --------
    >>> default_route("coupled"), default_route("coupled", "standard"), default_route("literal")
    ('settled', 'monolithic', 'modular')
    """
    if model == "literal":
        return "modular"
    return "settled" if semantics == "preemptive" and not count_states else "monolithic"


def paper_route(model: str, route: str, semantics: str = "preemptive", count_states: bool | None = None) -> PaperRoute:
    """The row of :data:`PAPER_ROUTES` that runs ``route`` on ``model``.

    Parameters
    ----------
    model : str
        ``"literal"`` or ``"coupled"``.
    route : str
        ``"modular"``, ``"monolithic"`` or ``"settled"``.
    semantics : str
        The forcibility semantics asked for.
    count_states : bool or None
        Whether the supervisor's states are to be counted.

    Returns
    -------
    PaperRoute

    Raises
    ------
    InputError
        An unknown model or route, or a route that is not exact for this model or
        semantics, or that builds no ``V`` to count; ``where`` names the parameter.

    Examples
    --------
    >>> paper_route("coupled", "settled").builds_supervisor
    False
    >>> paper_route("literal", "settled")
    Traceback (most recent call last):
    ...
    supcoord.errors.InputError: route: settled is a route of the coupled model (its collision events settle the levels); the literal model's routes are modular and monolithic
    """
    if model not in MODELS:
        raise InputError(f"must be literal or coupled, got {model!r}", value=model, where="model")
    if route not in ROUTES:
        raise InputError(f"must be modular, monolithic or settled, got {route!r}", value=route, where="route")
    row = _TABLE.get((model, route))
    if row is None:
        raise InputError(_WRONG_MODEL[route], value=route, where="route")
    # a route exact under both semantics leaves checking the name to ccc
    if row.semantics != SEMANTICS and semantics not in row.semantics:
        raise InputError(_WRONG_SEMANTICS, value=semantics, where="semantics")
    if count_states and not row.builds_supervisor:
        raise InputError(_NO_SUPERVISOR, value=route, where="route")
    return row


def route_rule(model: str, route: str, semantics: str) -> str | None:
    """The rule of :data:`PAPER_ROUTES` that a known ``route`` breaks on ``model`` under
    ``semantics``, in one short sentence (None: the table has the route).

    Examples
    --------
    >>> route_rule("coupled", "settled", "standard")
    'settled is a route of the coupled model under preemptive semantics'
    >>> route_rule("coupled", "settled", "preemptive") is None
    True
    """
    row = _TABLE.get((model, route))
    return None if row is not None and semantics in row.semantics else _RULES[route]
