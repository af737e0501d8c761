"""The kinds of case a study can hold, and the parameters of each.

A *case* is one computation: a kind and a complete set of parameters (defaults filled
in).  The kinds mirror the command line:

- ``paper``: the seed paper's model (:func:`supcoord.paper.run.run_paper`, ``supcoord
  paper``): ``positioners``, ``steps``, ``model``, ``route``, ``seed``, ``semantics``,
  ``count_transitions``; the routes and the rules of which model and semantics each
  takes are those of :data:`supcoord.paper.paper_routes.PAPER_ROUTES`;
- ``solve``: geometric coordination (:func:`supcoord.planning.planner.solve`, ``supcoord
  solve``) of a problem that is ``"random"`` (:func:`supcoord.problems.random.random_problem`:
  ``layout``, ``rings``, ``kinematics``, ``buffer``, ``seed``, ``priority``), ``"preset"``
  (:func:`supcoord.problems.presets.preset_problem`: ``instrument``, ``rings``, ``seed``,
  ``alpha_steps``, ``beta_steps``, ``start``) or a PROBLEM.json file; ``route``, ``order``,
  ``improve``, ``validate``;
- ``supcon``: ``V = supcon(G, allevents(G) || S)`` of a scalable family
  (:data:`supcoord.des.families.FAMILIES`: ``family``, ``size``, ``method``);
- ``force``: backtracking forcibility (:func:`supcoord.synthesis.ccc.ccc`) from the initial
  state of a family's supervisor (``family``, ``size``) or of a generator file
  (``generator``), to ``target`` (``"marked"``), in ``semantics``;
- ``call``: any importable function ``"module:name"`` with ``args`` and ``kwargs`` (a
  study of your own code; a returned dict is recorded as the case's results); ``size``
  and ``positioners`` are the case's x in tables and plots, and are passed to the
  function as keywords when it takes them (so they can be a grid axis).  The study's
  ``pythonpath`` folders are searched first for ``module``.

Each parameter is checked here, in the process that reads the study, so a mistake is one
line naming the file, the field and the value before anything runs.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..paper.paper_routes import MODELS, ROUTES, SEMANTICS, default_route, route_rule

__all__ = [
    "FAMILY_NAMES",
    "KINDS",
    "REQUIRED",
    "SUPCON_METHODS",
    "check_params",
    "default_route",
    "series_of",
    "size_of",
]

#: the marker of a parameter without default
REQUIRED = object()
#: :data:`supcoord.des.families.FAMILIES` (kept here so that reading a study imports no BDD package;
#: ``tests/study/test_study_spec.py`` checks they agree)
FAMILY_NAMES = ("dining_philosophers", "small_factories", "coupled_factories", "transfer_line_chain", "machine_line")
#: :data:`supcoord.synthesis.reachability.METHODS` (checked the same way)
SUPCON_METHODS = ("bfs", "chaining", "saturation")


# -- checkers: value -> normalized value, or ValueError with the reason ----------------------


def _int(least: int) -> Callable[[Any], int]:
    def check(v: Any) -> int:
        if isinstance(v, bool) or not isinstance(v, int) or v < least:
            raise ValueError(f"must be an integer >= {least}")
        return v
    return check


def _number(least: float = 0.0, strict: bool = False) -> Callable[[Any], float]:
    def check(v: Any) -> float:
        ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
        if not ok or v < least or (strict and v == least):
            raise ValueError(f"must be a number {'>' if strict else '>='} {least:g}")
        return float(v)
    return check


def _choice(*names: Any) -> Callable[[Any], Any]:
    def check(v: Any) -> Any:
        if v not in names:
            raise ValueError("must be one of " + ", ".join(repr(n) for n in names))
        return v
    return check


def _optional(inner: Callable[[Any], Any]) -> Callable[[Any], Any]:
    return lambda v: None if v is None else inner(v)


def _bool(v: Any) -> bool:
    if not isinstance(v, bool):
        raise TypeError("must be true or false")
    return v


def _text(v: Any) -> str:
    if not isinstance(v, str) or not v:
        raise ValueError("must be a non-empty string")
    return v


def _table(v: Any) -> dict:
    if not isinstance(v, dict):
        raise TypeError("must be a table (a JSON object)")
    return v


def _list(v: Any) -> list:
    if not isinstance(v, list):
        raise TypeError("must be a list")
    return v


def _function(v: Any) -> str:
    if not isinstance(v, str) or v.count(":") != 1 or not all(v.split(":")):
        raise ValueError("must be 'module:name', e.g. 'time:sleep'")
    return v


#: kind -> parameter -> (checker, default); a list of values is a grid axis
KINDS: dict[str, dict[str, tuple[Callable[[Any], Any], Any]]] = {
    "paper": {
        "positioners": (_int(1), REQUIRED), "steps": (_int(2), REQUIRED),
        "model": (_choice(*MODELS), "literal"), "route": (_optional(_choice(*ROUTES)), None),
        "seed": (_int(0), 0), "semantics": (_choice(*SEMANTICS), "preemptive"),
        "count_transitions": (_optional(_bool), None),
    },
    "solve": {
        "problem": (_text, REQUIRED), "layout": (_optional(_table), None), "rings": (_optional(_int(0)), None),
        "kinematics": (_optional(_table), None), "buffer": (_optional(_number()), None), "seed": (_int(0), 0),
        "priority": (_choice("random", "index"), "random"), "instrument": (_optional(_text), None),
        "alpha_steps": (_optional(_int(2)), None), "beta_steps": (_optional(_int(2)), None),
        "start": (_optional(_choice("random", "folded")), None),
        "route": (_choice("local", "monolithic"), "local"), "order": (_optional(_choice("rcm", "hex")), None),
        "improve": (_optional(_int(0)), None), "validate": (_bool, True),
    },
    "supcon": {"family": (_choice(*FAMILY_NAMES), REQUIRED), "size": (_int(1), REQUIRED),
               "method": (_choice(*SUPCON_METHODS), "saturation")},
    "force": {"family": (_optional(_choice(*FAMILY_NAMES)), None), "size": (_optional(_int(1)), None),
              "generator": (_optional(_text), None), "target": (_text, "marked"),
              "semantics": (_choice("preemptive", "standard"), "preemptive")},
    "call": {"function": (_function, REQUIRED), "args": (_list, []), "kwargs": (_table, {}),
             "size": (_optional(_int(0)), None), "positioners": (_optional(_int(0)), None)},
}
#: parameters whose value is itself a list: only a list of lists is a grid axis for them
LIST_VALUED = {"args"}
#: solve's problem sources besides a file name
PROBLEM_SOURCES = ("random", "preset")


def check_params(kind: str, params: dict[str, Any], where: str, base: Path | None = None) -> dict[str, Any]:
    """The complete parameters of one case of ``kind`` (defaults filled in, file names made
    absolute against ``base``), or an :class:`InputError` at ``where.FIELD``."""
    schema = KINDS[kind]
    unknown = sorted(set(params) - set(schema))
    if unknown:
        raise InputError(f"unknown field for kind {kind!r} (known: {', '.join(sorted(schema))})",
                         value=unknown[0], where=f"{where}.{unknown[0]}")
    out: dict[str, Any] = {}
    for name, (check, default) in schema.items():
        if name not in params:
            if default is REQUIRED:
                raise InputError(f"missing (kind {kind!r} needs it)", value=None, where=f"{where}.{name}")
            out[name] = default
            continue
        try:
            out[name] = check(params[name])
        except (ValueError, TypeError) as exc:
            raise InputError(f"{exc}, got {params[name]!r}", value=params[name], where=f"{where}.{name}") from None
    _check_combination(kind, out, where, base)
    return out


def _check_combination(kind: str, p: dict[str, Any], where: str, base: Path | None) -> None:
    def fail(field: str, message: str) -> None:
        raise InputError(message, value=p.get(field), where=f"{where}.{field}")

    if kind == "paper":
        if p["route"] is None:
            p["route"] = default_route(p["model"], p["semantics"])
        rule = route_rule(p["model"], p["route"], p["semantics"])  # the table of supcoord.paper.paper_routes
        if rule is not None:
            fail("route", f"{rule}; use route = 'monolithic'")
    elif kind == "solve":
        source = p["problem"]
        if source == "random":
            if p["kinematics"] is None:
                fail("kinematics", "missing (a random problem needs its kinematics, e.g. "
                                   "{kind = 'rotary', arm = 15.0, steps = 12})")
            if p["layout"] is None and p["rings"] is None:
                fail("rings", "missing (a random problem needs a layout or rings of a hex grid)")
            if p["instrument"] is not None:
                fail("instrument", "belongs to problem = 'preset'")
        elif source == "preset":
            if p["instrument"] is None:
                fail("instrument", "missing (problem = 'preset' needs an instrument, e.g. 'sdss-v')")
            for name in ("layout", "kinematics"):
                if p[name] is not None:
                    fail(name, "belongs to problem = 'random' (a preset has its own)")
        else:
            p["problem"] = _resolve(source, base, f"{where}.problem")
    elif kind == "force":
        if (p["generator"] is None) == (p["family"] is None):
            fail("family", "give either family (with size) or generator, not both or neither")
        if p["family"] is not None and p["size"] is None:
            fail("size", "missing (a family needs its size)")
        if p["generator"] is not None:
            p["generator"] = _resolve(p["generator"], base, f"{where}.generator")


def _resolve(name: str, base: Path | None, where: str) -> str:
    """A file named in a study, relative to the study file's folder; it must exist."""
    path = Path(name).expanduser()
    if not path.is_absolute() and base is not None:
        path = base / path
    if not path.is_file():
        raise InputError("file not found", value=name, where=where)
    return str(path.resolve())


def series_of(kind: str, p: dict[str, Any]) -> str:
    """The name of the curve a case belongs to (its kind and everything but size and seed)."""
    if kind == "paper":
        return f"paper {p['model']} {p['route']}" + ("" if p["semantics"] == "preemptive" else f" {p['semantics']}")
    if kind == "solve":
        if p["problem"] == "random":
            what = (p["kinematics"] or {}).get("kind", "random")
        elif p["problem"] == "preset":
            what = p["instrument"]
        else:
            what = Path(p["problem"]).stem
        return f"solve {what} {p['route']}"
    if kind == "supcon":
        return f"supcon {p['family']}" + ("" if p["method"] == "saturation" else f" {p['method']}")
    if kind == "force":
        what = p["family"] or Path(p["generator"]).stem
        return f"force {what} {p['semantics']}"
    return f"call {p['function']}"


def size_of(kind: str, p: dict[str, Any]) -> tuple[int | None, int | None]:
    """``(size, positioners)`` known before running: the x of the plots (a problem file's
    positioners are known only once it is read, in the case itself)."""
    if kind == "paper":
        return p["positioners"], p["positioners"]
    if kind == "solve":
        rings = p["rings"] if p["rings"] is not None else (p["layout"] or {}).get("rings")
        if p["problem"] in PROBLEM_SOURCES and isinstance(rings, int) and (p["layout"] or {}).get("kind", "hex") == "hex":
            n = 1 + 3 * rings * (rings + 1)
            return n, n
        return None, None
    if kind == "call":
        return p["size"] if p["size"] is not None else p["positioners"], p["positioners"]
    return p["size"], None
