"""The names of a pair table's indices, shared by every reader of the collision tables.

A pair table answers one question: does a move of one member of a neighbour pair collide
with the other standing?  Its entries are named the same way everywhere, in
:class:`.collision.CollisionTables` (the swept tables ``W``) and in
:mod:`supcoord.planning.guards` (the blocked tables ``B``):

- ``pair``: a neighbour pair ``k = (a, b)``, ``a < b``, an index into ``pairs``;
- ``mover``: which member moves, :attr:`Mover.A` (0, ``a``) or :attr:`Mover.B` (1, ``b``);
- ``move``: a one-step move of one joint, an index into :meth:`Kinematics.moves`;
- ``at_a``, ``at_b``: flat positions (:meth:`Kinematics.flat_position`) of ``a`` and ``b``;
- ``mover_at``, ``other_at``: flat positions of the member moving and of the one standing.

The swept tables keep ``a``'s positions on their second axis whoever moves
(``swept(pair, mover)[move, at_a, at_b]``); the blocked tables are oriented mover first
(``blocked_table(problem, pair, mover)[move, mover_at, other_at]``).  The readers that
take many entries at once take arrays of each index (:data:`Indices`, broadcast together)
and return :data:`Flags`.
"""

from __future__ import annotations

from enum import IntEnum
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

__all__ = ["Pair", "Mover", "MoveIndex", "Position", "Indices", "Flags"]

#: a neighbour pair: an index into ``CollisionTables.pairs`` (and ``Problem.pairs``)
Pair: TypeAlias = int
#: a one-step move of one joint: an index into ``Kinematics.moves()``
MoveIndex: TypeAlias = int
#: a flat position of one robot (``Kinematics.flat_position``)
Position: TypeAlias = int
#: integer indices, one per entry read (pairs, movers, moves or positions)
Indices: TypeAlias = NDArray[np.int_]
#: Boolean entries (True: the move collides, or is blocked)
Flags: TypeAlias = NDArray[np.bool_]


class Mover(IntEnum):
    """Which member of a pair ``(a, b)`` moves (plain ``0`` and ``1`` are accepted alike).

    Examples
    --------
    >>> Mover.A.other
    <Mover.B: 1>
    >>> int(Mover.B)
    1
    """

    A = 0
    B = 1

    @property
    def other(self) -> "Mover":
        """The member standing while this one moves."""
        return Mover(1 - self)
