"""Fixpoints over symbolic generators, each with an explicit reference twin."""

from .ccc import CCCResult, ccc
from .forcibility import Layers, bfa, forcible_layers, forcible_layers_naive
from .witness import forcing_paths, strategy, witness

__all__ = [
    "CCCResult",
    "Layers",
    "bfa",
    "ccc",
    "forcible_layers",
    "forcible_layers_naive",
    "forcing_paths",
    "strategy",
    "witness",
]
