"""Graphviz DOT export of small explicit generators.

Conventions (TCT/Wonham style): states are circles labelled by their name (or
number); marked states are double circles; an arrow from a point marks the initial
state; **controllable events are solid edges, uncontrollable events dashed edges**.
Several events between the same two states share one edge per controllability,
labelled ``a, b``.  Render with ``dot -Tpdf G.dot -o G.pdf``.
"""

from __future__ import annotations

import os

from ...errors import InputError
from ..generator import Generator
from .files import write_atomic

__all__ = ["DOT_MAX_STATES", "to_dot", "write_dot"]

#: the largest generator written as DOT (beyond it, a drawing is unreadable: use .gen)
DOT_MAX_STATES = 2000


def _quote(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def to_dot(g: Generator, max_states: int = DOT_MAX_STATES) -> str:
    """The DOT text of ``g``; raises :class:`InputError` beyond ``max_states`` states.

    >>> from supcoord.des.generator import Event
    >>> g = Generator(2, [Event("a", True), Event("u", False)], [(0, "a", 1), (1, "u", 0)], marked=[0])
    >>> print(to_dot(g).splitlines()[-2])
      "1" -> "0" [label="u", style=dashed];
    """
    if g.n_states > max_states:
        raise InputError(f"{g.name!r} has {g.n_states} states; DOT export is for at most {max_states}", value=g.n_states)
    lines = [f"digraph {_quote(g.name)} {{", "  rankdir=LR;", '  node [shape=circle, fontname="Helvetica"];',
             '  edge [fontname="Helvetica"];']
    if g.init is not None:
        lines += ["  __init [shape=point, width=0.08];", f'  __init -> "{g.init}";']
    for q in range(g.n_states):
        shape = ", shape=doublecircle" if q in g.marked else ""
        lines.append(f'  "{q}" [label={_quote(g.state_label(q))}{shape}];')
    edges: dict[tuple[int, int, bool], list[str]] = {}
    for s, e, t in g.transitions():
        edges.setdefault((s, t, g.events[e].controllable), []).append(e)
    for (s, t, c), evs in edges.items():
        style = "" if c else ", style=dashed"
        lines.append(f'  "{s}" -> "{t}" [label={_quote(", ".join(evs))}{style}];')
    lines.append("}")
    return "\n".join(lines) + "\n"


def write_dot(g: Generator, path: str | os.PathLike, max_states: int = DOT_MAX_STATES) -> None:
    """Write :func:`to_dot` of ``g`` to ``path``."""
    write_atomic(path, [to_dot(g, max_states)], "utf-8")
