"""Fixpoints over symbolic generators, each with an explicit reference twin.

See ``docs/synthesis.md`` for reachability/supcon definitions and conventions.
"""

from .ccc import CCCResult, ccc
from .checks import (
    check_deterministic,
    is_controllable,
    is_controllable_naive,
    is_nonblocking,
    is_nonblocking_naive,
    nondeterminism,
)
from .forcibility import Layers, bfa, forcible_layers, forcible_layers_naive
from .reachability import (
    METHODS,
    coreachable,
    coreachable_naive,
    event_clusters,
    reachable,
    reachable_naive,
    trim,
    trim_naive,
)
from .supcon import SupconResult, accessible_part, lift_spec, product, product_naive, supcon, supcon_naive
from .witness import forcing_paths, strategy, witness

__all__ = [
    "CCCResult",
    "Layers",
    "METHODS",
    "SupconResult",
    "bfa",
    "ccc",
    "check_deterministic",
    "coreachable",
    "coreachable_naive",
    "event_clusters",
    "forcible_layers",
    "forcible_layers_naive",
    "forcing_paths",
    "is_controllable",
    "is_controllable_naive",
    "is_nonblocking",
    "is_nonblocking_naive",
    "lift_spec",
    "nondeterminism",
    "product",
    "product_naive",
    "reachable",
    "reachable_naive",
    "strategy",
    "supcon",
    "accessible_part",
    "supcon_naive",
    "trim",
    "trim_naive",
    "witness",
]
