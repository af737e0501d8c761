"""Old import paths, kept for one release with a :class:`DeprecationWarning`.

Release 0.2 reorganised the package into one folder per idea (see ``docs/architecture.md``).
The modules users may have imported by their old names (``supcoord.positioners.*``,
``supcoord.symbolic.*`` and ``supcoord.des.io_*``) still import: each old name is an alias
module that warns once and forwards every attribute to the module's new home.

>>> import warnings
>>> import supcoord
>>> with warnings.catch_warnings():
...     warnings.simplefilter("ignore", DeprecationWarning)  # warned once, on the first import
...     from supcoord.positioners import solve
>>> solve is supcoord.solve.__wrapped__   # the same function (supcoord.solve checks its arguments first)
True
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings
from typing import Any

#: old module name -> new module name (relative to ``supcoord.``)
MOVED: dict[str, str] = {
    "symbolic": "bdd",
    "symbolic.context": "bdd.context",
    "symbolic.counting": "bdd.counting",
    "symbolic.cudd_count": "bdd.cudd_count",
    "symbolic.ordering": "bdd.ordering",
    "des.io_gen": "des.io.gen_file",
    "des.io_json": "des.io.json_file",
    "des.io_dot": "des.io.dot_file",
    "positioners.paper": "paper.literal",
    "positioners.paper_modular": "paper.modular",
    "positioners.paper_solve": "paper.run",
    "positioners.coupled": "paper.coupled",
    "positioners.demo": "paper.demo",
    "positioners.layout": "geometry.layout",
    "positioners.kinematics": "geometry.kinematics",
    "positioners.collision": "geometry.collision",
    "positioners.presets": "geometry.presets_table",
    "positioners.problem": "problems.problem",
    "positioners.plan": "problems.plan",
    "positioners.random_problems": "problems.random",
    "positioners.validate": "problems.validate",
    "positioners.coordination": "planning.model",
    "positioners.planner": "planning.planner",
    "positioners.planner_local": "planning.windows",
    "positioners.planner_descent": "planning.descent",
    "positioners.planner_forward": "planning.search",
    "positioners.planner_schedule": "planning.schedule",
    "positioners.planner_improve": "planning.improve",
    "positioners.planner_optimal": "planning.optimum",
    "positioners.search_naive": "testing.explicit_search",
    "positioners.figures": "figures.problem_figures",
    "positioners.figures_plan": "figures.plan_figures",
}

#: names of an old module that now live elsewhere than its main new home (looked up in order)
ALSO: dict[str, tuple[str, ...]] = {
    "positioners.presets": ("problems.presets",),
    "positioners.planner": ("planning.move_layers",),
    "positioners.figures": ("figures.plan_figures",),
    "positioners.coordination": ("planning.guards", "planning.graph_order"),
    "positioners.planner_forward": ("bdd.context",),
}

#: names of release 0.1 removed: dead code (nothing used it), and the constant robot limit (now set by
#: memory: :mod:`supcoord.geometry.layout_limits`)
REMOVED: dict[str, tuple[str, ...]] = {"positioners.coordination": ("order_bandwidth",),
                                       "positioners.problem": ("MAX_POSITIONERS",)}

#: the old ``supcoord.positioners`` package's ``__all__``: name -> new module
POSITIONERS_NAMES: dict[str, str] = {}  # filled below

_PREFIX = "supcoord."


def _positioners_names() -> dict[str, str]:
    geometry = ["hex_count", "hex_grid", "layout_from_spec", "points_layout", "AlphaBeta", "Joint", "Kinematics",
                "Rotary", "kinematics_from_spec", "CollisionTables", "colliding_pairs", "motion_collides",
                "neighbour_pairs", "segment_distance", "simultaneous_table", "static_table", "swept_table",
                "PRESETS", "Preset"]
    problems = ["Problem", "load_problem", "parse_problem", "Plan", "compact_moves", "event_name", "load_plan",
                "lower_bound", "parse_event", "parse_plan", "plan_from_moves", "validate_plan",
                "random_configuration", "random_problem", "preset_problem"]
    planning = ["CoordinationModel", "conflict_components", "rcm_order", "solve"]
    testing = ["bfs_plan_naive", "optimal_makespan_naive"]
    names = {}
    for pkg, group in (("geometry", geometry), ("problems", problems), ("planning", planning), ("testing", testing)):
        names.update({n: pkg for n in group})
    return names


POSITIONERS_NAMES.update(_positioners_names())


def _warn(old: str, new: str) -> None:
    warnings.warn(f"{old} is deprecated and will be removed in supcoord 0.3: use {new}",
                  DeprecationWarning, stacklevel=3)


class _Alias(types.ModuleType):
    """A module that forwards attribute look-ups to its new home (imported on first use)."""

    def __init__(self, old: str, new: str | None, names: dict[str, str] | None = None) -> None:
        super().__init__(old)
        self._new, self._names = new, names or {}
        self._homes = () if new is None else (new, *ALSO.get(old[len(_PREFIX):], ()))
        if names:
            self.__all__ = sorted(names)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        if name in self._names:
            return getattr(importlib.import_module(_PREFIX + self._names[name]), name)
        if self._homes:
            for home in self._homes:
                module = importlib.import_module(_PREFIX + home)
                if hasattr(module, name):
                    return getattr(module, name)
            raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")
        sub = f"{self.__name__}.{name}"  # ``from supcoord.positioners import planner``
        if sub[len(_PREFIX):] in MOVED:
            return importlib.import_module(sub)
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")

    def __dir__(self) -> list[str]:
        if self._new is not None:
            return dir(importlib.import_module(_PREFIX + self._new))
        return sorted(self._names)


class _Loader(importlib.abc.Loader):
    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        old = spec.name[len(_PREFIX):]
        if old == "positioners":
            module = _Alias(spec.name, None, POSITIONERS_NAMES)
            new = "supcoord.geometry, supcoord.problems, supcoord.planning or supcoord.testing"
        else:
            module = _Alias(spec.name, MOVED[old])
            new = _PREFIX + MOVED[old]
        _warn(spec.name, new)
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        return None


class _Finder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname: str, path: Any = None, target: Any = None) -> importlib.machinery.ModuleSpec | None:
        if not fullname.startswith(_PREFIX):
            return None
        old = fullname[len(_PREFIX):]
        if old == "positioners" or old in MOVED:
            is_package = old in ("positioners", "symbolic")
            return importlib.machinery.ModuleSpec(fullname, _Loader(), is_package=is_package)
        return None


def install() -> None:
    """Put the alias finder first on ``sys.meta_path`` (idempotent)."""
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.insert(0, _Finder())
