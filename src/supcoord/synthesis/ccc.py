"""The Complete Coordination Checker (CCC) of the seed paper, symbolically.

``CCC(V)`` holds iff ``BFA(V, q0, Qm) ≠ ∅``, i.e. iff ``q0 ∈ W(∞)`` for the
forcibility fixpoint with target ``T = Qm`` (:mod:`.forcibility`)::

    CCC(V) = [q0 ∈ W(∞)],  W(0) = Qm,  W(k+1) = W(k) ∪ Force(W(k))

It reports, besides the verdict, ``rank(q0)`` (the worst-case number of events to the
target), a witness string (:func:`~.witness.witness`) and the exact layer sizes.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, Supervisory coordination of robotic fiber
  positioners in multi-object spectrographs, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (Algorithm CCC).
- M. Macktoobian, W. M. Wonham, Automatic reconfiguration of untimed discrete-event
  systems, ICEEE 2017.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

from ..des.symbolic import SymbolicGenerator
from ..progress import summary_html, summary_repr
from .forcibility import forcible_layers
from .layers import Layers
from .witness import witness

__all__ = ["CCCResult", "ccc"]


@dataclass
class CCCResult:
    """The verdict of :func:`ccc`: ``forcible``, a ``witness`` string (empty when not
    forcible), ``rank`` of the initial state (None when not forcible), exact ``layers``
    sizes, ``stats`` (seconds, iterations, BDD nodes), and the :class:`Layers` themselves."""

    forcible: bool
    witness: list[str]
    rank: int | None
    layers: list[int]
    stats: dict[str, Any] = field(default_factory=dict)
    fixpoint: Layers | None = field(default=None, repr=False, compare=False)

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: the verdict, the rank, the witness's length and first events."""
        out: dict[str, Any] = {"forcible": self.forcible, "rank": self.rank, "layers": len(self.layers)}
        if self.witness:
            out["witness"] = " ".join(map(str, self.witness[:8])) + (f" … ({len(self.witness)} events)"
                                                                     if len(self.witness) > 8 else "")
        if "seconds" in (self.stats or {}):
            out["seconds"] = round(float(self.stats["seconds"]), 3)
        return out

    def __repr__(self) -> str:
        return summary_repr("CCCResult", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("CCCResult", self.summary())

    def to_json(self) -> dict[str, Any]:
        """The ``supcoord force --json`` object of ``docs/formats.md``."""
        return {
            "status": "ok",
            "forcible": self.forcible,
            "witness": list(self.witness),
            "rank": self.rank,
            "layers": list(self.layers),
        }


def ccc(V: SymbolicGenerator, semantics: str = "preemptive", *, target: Any = None, full: bool = True) -> CCCResult:
    """Complete Coordination Checker: is ``V``'s marked set (or ``target``) forcible from ``q0``?

    ``CCC(V) = [q0 ∈ W(∞)]`` for the backtracking-forcibility fixpoint
    ``W(0) = T``, ``W(k+1) = W(k) ∪ Force(W(k))`` (:func:`~.forcibility.force`).

    Parameters
    ----------
    V : SymbolicGenerator
        The supervisor (any deterministic symbolic generator), typically
        ``supcon(G, allevents(G) || S).supervisor``.
    semantics : {"preemptive", "standard"}, optional
        ``"preemptive"`` (the seed paper's Remark): where an uncontrollable event is
        pending, all of them must lead into ``W``, and elsewhere one controllable event
        must; ``"standard"``: one controllable event into ``W`` and every uncontrollable
        one too.
    target : BDD or state, optional
        The set to force (default ``V``'s marked states): a BDD over ``V``'s variables
        or a state as :func:`~.layers.as_states` reads it.
    full : bool, optional
        ``False`` stops the fixpoint as soon as ``q0`` is won (the layer sizes are
        then those of ``W(rank(q0))``).

    Returns
    -------
    CCCResult
        ``forcible``; ``witness`` (a shortest forcing string of event names, empty when
        not forcible); ``rank`` (events to the target in the worst case, ``None`` when
        not forcible); ``layers`` (exact state counts of ``L(0), L(1), …``); ``stats``
        (``seconds`` wall-clock s, ``winning_states``, ``complete``, the fixpoint's
        ``iterations`` and BDD nodes); ``fixpoint`` (the :class:`Layers`).  An empty
        ``V`` (no initial state) is not forcible.

    Raises
    ------
    InputError
        ``semantics`` is unknown, or ``target`` is no state or set of ``V``.
    BudgetExceeded
        The context's node or time budget ran out.

    See Also
    --------
    supcoord.synthesis.forcibility.forcible_layers : the layers alone.
    supcoord.synthesis.forcibility.bfa : the forcible paths from ``q0``.

    References
    ----------
    .. [1] M. Macktoobian, D. Gillet, J.-P. Kneib, "Supervisory coordination of robotic
       fiber positioners in multi-object spectrographs", IFAC-PapersOnLine 52(3), 2019,
       doi:10.1016/j.ifacol.2019.06.011 (Algorithm CCC).
    .. [2] M. Macktoobian, W. M. Wonham, "Automatic reconfiguration of untimed
       discrete-event systems", ICEEE 2017 (backtracking forcibility).

    Examples
    --------
    >>> from supcoord.des.generator import Event, Generator
    >>> from supcoord.des.symbolic import from_explicit
    >>> from supcoord.bdd import Context
    >>> g = Generator(3, [Event("a", True), Event("u", False)], [(0, "a", 1), (1, "u", 2)], 0, [2])
    >>> r = ccc(from_explicit(Context(), g))
    >>> r.forcible, r.witness, r.rank, r.layers
    (True, ['a', 'u'], 2, [1, 1, 1])
    >>> ccc(from_explicit(Context(), g), "standard").forcible  # u alone at 1: no event to force
    False
    """
    started = time.perf_counter()
    T = V.marked if target is None else target
    lay = forcible_layers(V, T, semantics=semantics, stop_at=None if full or V.init == V.ctx.false else V.init)
    r = lay.rank(V.init) if V.init != V.ctx.false else None
    w = witness(V, lay, V.init) if r is not None else []
    sizes = lay.sizes()
    stats = dict(lay.stats)
    stats.update(seconds=time.perf_counter() - started, winning_states=sum(sizes), complete=lay.complete)
    return CCCResult(r is not None, w, r, sizes, stats, lay)
