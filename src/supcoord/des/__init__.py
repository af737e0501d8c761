"""Generators: explicit (TCT-like) and symbolic, their compositions and file formats."""

from . import classic, explicit_ops, families, symbolic_ops
from .generator import Event, Generator, merge_alphabets, tct_event
from .io import read_generator, write_generator
from .symbolic import EventRelation, SymbolicGenerator, from_explicit, to_explicit

__all__ = [
    "Event",
    "EventRelation",
    "Generator",
    "SymbolicGenerator",
    "classic",
    "explicit_ops",
    "families",
    "from_explicit",
    "merge_alphabets",
    "read_generator",
    "symbolic_ops",
    "tct_event",
    "to_explicit",
    "write_generator",
]
