"""supcoord: supervisory coordination of robotic fiber positioners with BDDs.

Layers (imports go downward only): :mod:`supcoord.symbolic` (the BDD context),
:mod:`supcoord.des` (generators and formats), :mod:`supcoord.synthesis` (fixpoints),
:mod:`supcoord.positioners` (the domain), :mod:`supcoord.cli` (command line).
"""

__version__ = "0.1.0"

from .errors import (  # noqa: E402
    AlphabetError,
    BudgetExceeded,
    FormatError,
    InputError,
    ModelError,
    NondeterminismError,
    SupcoordError,
)

__all__ = [
    "__version__",
    "AlphabetError",
    "BudgetExceeded",
    "FormatError",
    "InputError",
    "ModelError",
    "NondeterminismError",
    "SupcoordError",
]
