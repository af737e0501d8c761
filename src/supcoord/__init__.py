"""supcoord: supervisory coordination of robotic fiber positioners, computed with BDDs.

Each positioner and its target are discrete-event systems; the coordination
supervisor is ``V = supcon(G, allevents(G) || S)`` and the Complete Coordination
Checker ``ccc(V)`` decides, by backtracking forcibility, whether ``V`` can force its
marked state from its initial state, returning the forcing event string.  States,
counters and transition relations are BDDs, so this scales to thousands of positioners.

The seed paper's example (positioners P1–P3 starting at ``[0], [6], [6]``, collisions
driven by the arms' geometry — the *coupled* reading, ``docs/paper.md``):

>>> import supcoord as sc
>>> inst = sc.paper_example()                 # 3 positioners, 8 positions each
>>> G, E = sc.coupled_models(sc.CoupledModel(inst))   # G and allevents(G) || S
>>> result = sc.supcon(G, E)
>>> V = result.supervisor
>>> result.stats["states"], result.stats["marked"]
(4128, 1)
>>> verdict = sc.ccc(V)                       # preemptive semantics (the paper's Remark)
>>> verdict.forcible, verdict.rank
(True, 6)
>>> verdict.witness                           # Table-1 labels
['10', '20', '15', '50', '83', '93']
>>> sc.describe(verdict.witness[2])
'P1 escapes clockwise by priority (h)'
>>> sc.ccc(V, "standard").forcible            # without preemption: not forcible
False

The public names (everything in ``__all__``) are imported lazily on first use, so
``import supcoord`` itself loads neither the BDD package nor matplotlib.  ``_LAZY``
below is their one source (name -> module); this table and the ``TYPE_CHECKING``
imports at the end are checked against it by ``tests/architecture/test_public_api_source.py``.

=================  ==========================================================
group              names
=================  ==========================================================
BDD layer          :class:`Context`, :class:`Budget`
generators         :class:`Event`, :class:`Generator`, :func:`tct_event`,
                   :class:`SymbolicGenerator`, :func:`from_explicit`,
                   :func:`to_explicit`, :func:`sync`, :func:`allevents`,
                   :func:`read_generator`, :func:`write_generator`, :func:`to_dot`
synthesis          :func:`supcon`, :func:`lift_spec`, :func:`reachable`,
                   :func:`coreachable`, :func:`is_controllable`,
                   :func:`is_nonblocking`, :class:`SupconResult`
forcibility        :func:`forcible_layers`, :class:`Layers`, :func:`bfa`,
                   :func:`witness`, :func:`forcing_paths`, :func:`strategy`,
                   :func:`ccc`, :class:`CCCResult`
the paper's model  :func:`paper_example`, :func:`random_instance`,
                   :class:`PaperInstance`, :func:`literal_models`,
                   :class:`CoupledModel`, :class:`Geometry`,
                   :func:`coupled_models`, :func:`settled_ccc`,
                   :func:`event_label`, :func:`decode_label`,
                   :func:`describe`, :func:`run_demo`,
                   :func:`solve_paper`, :func:`run_paper`, :class:`PaperRun`
geometric problems :class:`Problem`, :func:`load_problem`, :func:`parse_problem`,
                   :func:`random_problem`, :func:`preset_problem`,
                   :data:`PRESETS`, :class:`Plan`, :func:`load_plan`,
                   :func:`plan_from_moves`, :func:`validate_plan`,
                   :class:`ValidationResult`,
                   :func:`solve` (a problem -> a validated plan or a
                   certificate of infeasibility)
real woks          :func:`load_instrument`, :func:`folded_configuration`,
                   :func:`random_wok_targets`, :func:`wok_targets`,
                   :func:`wok_problem` (PROBLEM.json objects on SDSS-V's woks)
progress           :func:`progress_bar`, :class:`ProgressBar`,
                   :class:`ProgressLog` (``progress=`` callbacks)
figures            :func:`plot_problem`, :func:`save_plan_strip`,
                   :func:`save_plan_gif` (these import matplotlib)
errors             :class:`SupcoordError` and its subclasses
=================  ==========================================================

Layers (imports go downward only; ``docs/architecture.md`` has the exact table):
:mod:`supcoord.bdd` (the BDD context), :mod:`supcoord.des` (generators and formats),
:mod:`supcoord.synthesis` (fixpoints), :mod:`supcoord.paper` (the seed paper's
model); :mod:`supcoord.geometry`, :mod:`supcoord.instruments` and
:mod:`supcoord.problems` (focal planes, problems, plans, the validator),
:mod:`supcoord.planning` (the planner), :mod:`supcoord.figures`,
:mod:`supcoord.study` (declared studies), :mod:`supcoord.cli` (command line).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from . import _compat, errors
from .errors import (
    AlphabetError,
    BudgetExceeded,
    FormatError,
    InputError,
    ModelError,
    NondeterminismError,
    SupcoordError,
)

__version__ = "0.2.0"

_compat.install()  # release 0.1's module paths (supcoord.positioners.*, ...) import with a DeprecationWarning

#: public name -> module it lives in (imported on first attribute access): the one source of
#: the public API; the docstring's table and the TYPE_CHECKING block below must agree with it
_LAZY: dict[str, str] = {
    # the BDD layer
    "Context": "supcoord.bdd.context",
    "Budget": "supcoord.bdd.context",
    # generators and file formats
    "Event": "supcoord.des.generator",
    "Generator": "supcoord.des.generator",
    "tct_event": "supcoord.des.generator",
    "SymbolicGenerator": "supcoord.des.symbolic",
    "from_explicit": "supcoord.des.symbolic",
    "to_explicit": "supcoord.des.symbolic",
    "read_generator": "supcoord.des.io",
    "write_generator": "supcoord.des.io",
    "to_dot": "supcoord.des.io.dot_file",
    # synthesis
    "supcon": "supcoord.synthesis.supcon",
    "SupconResult": "supcoord.synthesis.supcon",
    "lift_spec": "supcoord.synthesis.supcon",
    "reachable": "supcoord.synthesis.reachability",
    "coreachable": "supcoord.synthesis.reachability",
    "is_controllable": "supcoord.synthesis.checks",
    "is_nonblocking": "supcoord.synthesis.checks",
    # forcibility and the Complete Coordination Checker
    "forcible_layers": "supcoord.synthesis.forcibility",
    "Layers": "supcoord.synthesis.forcibility",
    "bfa": "supcoord.synthesis.forcibility",
    "witness": "supcoord.synthesis.witness",
    "forcing_paths": "supcoord.synthesis.witness",
    "strategy": "supcoord.synthesis.witness",
    "ccc": "supcoord.synthesis.ccc",
    "CCCResult": "supcoord.synthesis.ccc",
    # the seed paper's model
    "PaperInstance": "supcoord.paper.literal",
    "paper_example": "supcoord.paper.literal",
    "random_instance": "supcoord.paper.literal",
    "literal_models": "supcoord.paper.literal",
    "event_label": "supcoord.paper.literal",
    "decode_label": "supcoord.paper.literal",
    "CoupledModel": "supcoord.paper.coupled",
    "Geometry": "supcoord.paper.coupled",
    "coupled_models": "supcoord.paper.coupled",
    "settled_ccc": "supcoord.paper.settled",
    "describe": "supcoord.paper.demo",
    "run_demo": "supcoord.paper.demo",
    "solve_paper": "supcoord.paper.run",
    "run_paper": "supcoord.paper.run",
    "PaperRun": "supcoord.paper.run",
    # geometric coordination problems
    "Problem": "supcoord.problems.problem",
    "load_problem": "supcoord.problems.problem",
    "parse_problem": "supcoord.problems.problem",
    "random_problem": "supcoord.problems.random",
    "preset_problem": "supcoord.problems.presets",
    "PRESETS": "supcoord.geometry.presets_table",
    "Plan": "supcoord.problems.plan",
    "load_plan": "supcoord.problems.plan",
    "plan_from_moves": "supcoord.problems.plan",
    "validate_plan": "supcoord.problems.validate",
    "ValidationResult": "supcoord.problems.validate",
    # real woks: starts and targets of problems on them
    "load_instrument": "supcoord.instruments",
    "folded_configuration": "supcoord.instruments",
    "random_wok_targets": "supcoord.instruments",
    "wok_targets": "supcoord.instruments",
    "wok_problem": "supcoord.instruments",
    "solve": "supcoord.planning.planner",
    # progress of long fixpoints
    "progress_bar": "supcoord.progress",
    "ProgressBar": "supcoord.progress",
    "ProgressLog": "supcoord.progress",
    # figures (matplotlib, Agg backend)
    "plot_problem": "supcoord.figures",
    "save_plan_strip": "supcoord.figures",
    "save_plan_gif": "supcoord.figures",
}

__all__ = sorted(
    [
        "__version__",
        "sync",
        "allevents",
        *errors.__all__,
        *_LAZY,
    ]
)


def sync(*generators: Any, name: str | None = None) -> Any:
    """The synchronous product ``G1 || G2 || …`` of explicit or of symbolic generators.

    An event moves every component that has it in its alphabet, and only if all of
    them can.  All arguments must be :class:`Generator` (explicit, the result is one)
    or all :class:`SymbolicGenerator` over one :class:`Context`.

    >>> from supcoord import Event, Generator, sync
    >>> a, b, c = Event("a", True), Event("b", True), Event("c", False)
    >>> G1 = Generator(2, [a, c], [(0, "a", 1), (1, "c", 0)], 0, [0])
    >>> G2 = Generator(2, [b, c], [(0, "b", 1), (1, "c", 0)], 0, [0])
    >>> G = sync(G1, G2)
    >>> G.n_states, sorted(G.enabled(G.run(["a", "b"])))
    (4, ['c'])
    """
    from .des import explicit_ops, symbolic_ops
    from .des.generator import Generator
    from .des.symbolic import SymbolicGenerator

    if not generators:
        raise InputError("sync needs at least one generator", value=0)
    if all(isinstance(g, Generator) for g in generators):
        return generators[0] if len(generators) == 1 and name is None else explicit_ops.sync(*generators, name=name)
    if all(isinstance(g, SymbolicGenerator) for g in generators):
        return symbolic_ops.sync(*generators, name=name)
    kinds = sorted({type(g).__name__ for g in generators})
    raise InputError(f"sync takes all explicit or all symbolic generators, got {', '.join(kinds)}", value=kinds)


def allevents(G: Any, name: str = "ALL") -> Any:
    """TCT's ``allevents(G)``: one marked state with a self-loop of every event of ``G``.

    Explicit for a :class:`Generator`, symbolic (in ``G``'s context) for a
    :class:`SymbolicGenerator`.  The paper writes the specification as
    ``allevents(G) || S`` so that ``supcon`` (TCT's meaning) sees ``S`` over ``G``'s
    alphabet.

    >>> from supcoord import Event, Generator, allevents
    >>> G = Generator(2, [Event("a", True), Event("u", False)], [(0, "a", 1), (1, "u", 0)], 0, [0])
    >>> A = allevents(G)
    >>> A.n_states, sorted(A.enabled(0))
    (1, ['a', 'u'])
    """
    from .des import explicit_ops, symbolic_ops
    from .des.generator import Generator
    from .des.symbolic import SymbolicGenerator

    if isinstance(G, SymbolicGenerator):
        return symbolic_ops.allevents(G.ctx, G, name=name)
    if isinstance(G, Generator):
        return explicit_ops.allevents(G, name=name)
    raise InputError(f"allevents takes a Generator or SymbolicGenerator, got {type(G).__name__}", value=G)


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'supcoord' has no attribute {name!r}")
    from ._boundary import checked  # here, not at the top: `import supcoord` stays instant

    value = checked(getattr(importlib.import_module(module), name))  # arguments checked at the boundary
    globals()[name] = value  # cache: the next access is a plain attribute
    return value


def __dir__() -> list[str]:
    """The public API (``__all__``): not the helpers this module imports for itself."""
    return list(__all__)


if TYPE_CHECKING:  # static type checkers and IDEs see the real objects
    from .bdd.context import Budget, Context
    from .des.generator import Event, Generator, tct_event
    from .des.io import read_generator, write_generator
    from .des.io.dot_file import to_dot
    from .des.symbolic import SymbolicGenerator, from_explicit, to_explicit
    from .figures import plot_problem, save_plan_gif, save_plan_strip
    from .geometry.presets_table import PRESETS
    from .instruments import folded_configuration, load_instrument, random_wok_targets, wok_problem, wok_targets
    from .paper.coupled import CoupledModel, Geometry, coupled_models
    from .paper.demo import describe, run_demo
    from .paper.literal import PaperInstance, decode_label, event_label, literal_models, paper_example, random_instance
    from .paper.run import PaperRun, run_paper, solve_paper
    from .paper.settled import settled_ccc
    from .planning.planner import solve
    from .problems.plan import Plan, load_plan, plan_from_moves
    from .problems.presets import preset_problem
    from .problems.problem import Problem, load_problem, parse_problem
    from .problems.random import random_problem
    from .problems.validate import ValidationResult, validate_plan
    from .progress import ProgressBar, ProgressLog, progress_bar
    from .synthesis.ccc import CCCResult, ccc
    from .synthesis.checks import is_controllable, is_nonblocking
    from .synthesis.forcibility import Layers, bfa, forcible_layers
    from .synthesis.reachability import coreachable, reachable
    from .synthesis.supcon import SupconResult, lift_spec, supcon
    from .synthesis.witness import forcing_paths, strategy, witness
