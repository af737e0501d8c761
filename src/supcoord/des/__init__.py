"""Generators: explicit (TCT-like) and symbolic, their compositions and file formats."""

from . import explicit_ops, symbolic_ops
from .generator import Event, Generator, merge_alphabets, tct_event
from .symbolic import EventRelation, SymbolicGenerator, from_explicit, to_explicit

__all__ = [
    "Event",
    "EventRelation",
    "Generator",
    "SymbolicGenerator",
    "explicit_ops",
    "from_explicit",
    "merge_alphabets",
    "symbolic_ops",
    "tct_event",
    "to_explicit",
]
