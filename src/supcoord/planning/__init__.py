"""Geometric coordination: a problem -> a validated plan or a certificate of infeasibility.

The guarded model (:mod:`.model`) encodes every positioner's moves as BDD relations
guarded by the collision tables (:mod:`.guards`), its variables ordered along the
conflict graph (:mod:`.graph_order`); :func:`solve` runs one of the planner's routes
(:mod:`.routes`) on it: the seed paper's supcon + forcibility on the whole grid
(:class:`Monolithic`) or exact windows (:class:`Local`: :mod:`.descent`, :mod:`.search`,
:mod:`.windows`), then, after a certificate, a finer lattice (:class:`FinerLattice`) and the
simultaneous model (:class:`Simultaneous`); it schedules (:mod:`.schedule`) and shortens
(:mod:`.improve`, :mod:`.pair_replan`) the plan; :mod:`.optimum` computes the optimal
makespan of small problems.
"""

from .graph_order import conflict_components, rcm_order
from .model import CoordinationModel
from .planner import solve
from .routes import ROUTES, FinerLattice, Local, Monolithic, Simultaneous

__all__ = ["CoordinationModel", "FinerLattice", "Local", "Monolithic", "ROUTES", "Simultaneous",
           "conflict_components", "rcm_order", "solve"]
