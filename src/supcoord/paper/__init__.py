"""The seed paper's model: each positioner and its target as discrete-event systems.

Macktoobian, Gillet, Kneib, *Supervisory coordination of robotic fiber positioners in
multi-object spectrographs*, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011.

Two readings (``docs/paper.md``): :mod:`.literal` (the model as printed, with an exact
modular route in :mod:`.modular` that scales linearly) and :mod:`.coupled` (collision
events driven by the arms' geometry, whose CCC :mod:`.settled` answers on its settled
states without building ``V``); :mod:`.events` numbers the events as Table 1.
:mod:`.run` runs either at a given size; :mod:`.demo` reproduces the paper's
three-positioner example end to end.
"""

from .coupled import CoupledModel, Geometry, coupled_models
from .demo import describe, run_demo
from .literal import PaperInstance, decode_label, event_label, literal_models, paper_example, random_instance
from .run import PaperRun, run_paper, solve_paper
from .settled import settled_ccc

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
