"""The seed paper's model: each positioner and its target as discrete-event systems.

Macktoobian, Gillet, Kneib, *Supervisory coordination of robotic fiber positioners in
multi-object spectrographs*, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011.

Two readings (``docs/paper.md``): :mod:`.literal` (the model as printed, with an exact
modular route in :mod:`.modular` that scales linearly) and :mod:`.coupled` (collision
events driven by the arms' geometry, whose CCC :mod:`.settled` answers on its settled
states without building ``V``); :mod:`.events` numbers the events as Table 1.
:mod:`.run` runs either at a given size; :mod:`.demo` reproduces the paper's
three-positioner example end to end; :mod:`.paper_routes` is the table of routes.  The names
below are imported on first use.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .coupled import CoupledModel, Geometry, coupled_models
    from .demo import describe, run_demo
    from .literal import PaperInstance, decode_label, event_label, literal_models, paper_example, random_instance
    from .run import PaperRun, run_paper, solve_paper
    from .settled import settled_ccc

#: public name -> its module; imported on first use, so that :mod:`.paper_routes` (which the study
#: reads) loads no BDD package
_HOMES = {
    "CoupledModel": "coupled", "Geometry": "coupled", "coupled_models": "coupled",
    "describe": "demo", "run_demo": "demo",
    "PaperInstance": "literal", "decode_label": "literal", "event_label": "literal", "literal_models": "literal",
    "paper_example": "literal", "random_instance": "literal",
    "PaperRun": "run", "run_paper": "run", "solve_paper": "run",
    "settled_ccc": "settled",
}

__all__ = [
    "CoupledModel",
    "Geometry",
    "PaperInstance",
    "PaperRun",
    "coupled_models",
    "decode_label",
    "describe",
    "event_label",
    "literal_models",
    "paper_example",
    "random_instance",
    "run_demo",
    "run_paper",
    "settled_ccc",
    "solve_paper",
]


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first use (and a submodule by its name)."""
    if name in _HOMES:
        value = getattr(importlib.import_module(f"{__name__}.{_HOMES[name]}"), name)
        globals()[name] = value
        return value
    try:
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
