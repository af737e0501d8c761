"""Geometric coordination: a problem -> a validated plan or a certificate of infeasibility.

The guarded model (:mod:`.model`) encodes every positioner's moves as BDD relations
guarded by the collision tables (:mod:`.guards`), its variables ordered along the
conflict graph (:mod:`.graph_order`); :func:`solve` runs the seed paper's supcon +
forcibility on it, on the whole grid (``route="monolithic"``) or in exact windows
(``route="local"``: :mod:`.descent`, :mod:`.search`, :mod:`.windows`), then schedules
(:mod:`.schedule`) and shortens (:mod:`.improve`, :mod:`.pair_replan`) the plan; :mod:`.optimum` computes the
optimal makespan of small problems.
"""

from .graph_order import conflict_components, rcm_order
from .model import CoordinationModel
from .planner import ROUTES, solve

__all__ = ["CoordinationModel", "ROUTES", "conflict_components", "rcm_order", "solve"]
