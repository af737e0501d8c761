"""Random problems on an instrument's geometry (a hex grid of the preset's pitch and arms).

The instrument numbers live in :mod:`supcoord.geometry.presets_table`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..geometry.layout import hex_count
from ..geometry.layout_limits import check_robot_count
from ..geometry.presets_table import Preset, folded_position, get_preset, preset_kinematics
from .problem import Problem
from .random import random_problem

__all__ = ["preset_problem"]


def preset_problem(name: str, rings: int | None = 2, seed: int = 0, *, alpha_steps: int = 36, beta_steps: int = 19,
                   pitch: float | None = None, buffer: float | None = None, start: str = "random",
                   near: int | None = None, priority: str = "random") -> Problem:
    """A random problem on a hex grid of ``rings`` rings of a preset instrument's geometry.

    Parameters
    ----------
    name : str
        The preset: ``"sdss-v"``, ``"desi"``, ``"moons"``, ``"pfs"``, ``"spec-s5"``, ``"must"`` or
        ``"wst"`` (case-insensitive).
    rings : int or None, default 2
        Rings of the hex grid around the centre robot (``1 + 3·R·(R+1)`` robots), as many as
        memory allows (:mod:`supcoord.geometry.layout_limits`); ``None``: the preset's whole
        focal plane (:attr:`~supcoord.geometry.presets_table.Preset.rings`, the next-generation
        presets).
    seed : int, default 0
        Seed of the random start, target and priority.
    alpha_steps, beta_steps : int
        Positions of each joint's lattice.
    pitch : float, optional
        Distance between neighbouring bases (mm); default the preset's (MOONS has none).
    buffer : float, optional
        Each robot's buffer (mm); default the preset's.
    start : {"random", "folded"}
        Random collision-free starts, or every robot at :func:`folded_position`.
    near : int, optional
        Targets at most this many lattice steps from the start per joint (default: anywhere).
    priority : str, default "random"
        ``"random"`` (a seeded permutation of ``1..N``) or ``"index"`` (``1..N`` in layout order).

    Returns
    -------
    Problem
        Named ``"<preset>-r<rings>-s<seed>"``; the same arguments give the same problem.

    Raises
    ------
    InputError
        An unknown preset, no pitch for a preset without one, ``rings`` not a non-negative
        integer or more robots than memory allows, an unknown ``start``, or arguments
        :func:`~supcoord.problems.random.random_problem` refuses.

    Examples
    --------
    >>> p = preset_problem("sdss-v", rings=1, seed=3, alpha_steps=12, beta_steps=7)
    >>> p.n, p.kinematics.shape, float(p.buffers[0]), p.extra["name"]
    (7, (12, 7), 2.0, 'sdss-v-r1-s3')
    >>> preset_problem("moons")
    Traceback (most recent call last):
    ...
    supcoord.errors.InputError: preset 'moons' has no pitch in our sources: pass pitch=... (mm)

    References
    ----------
    Each preset's numbers and their sources: :mod:`supcoord.geometry.presets_table`,
    ``docs/references.md``.
    """
    p = get_preset(name)
    pitch = pitch if pitch is not None else p.pitch
    if pitch is None:
        raise InputError(f"preset {p.name!r} has no pitch in our sources: pass pitch=... (mm)", value=name)
    rings = _rings(p, rings)
    kin = preset_kinematics(name, alpha_steps, beta_steps)
    layout = {"kind": "hex", "rings": rings, "pitch": float(pitch)}
    n = hex_count(rings)
    check_robot_count(n, "rings", rings)
    if start == "folded":
        fixed = np.tile(folded_position(kin), (n, 1))
    elif start == "random":
        fixed = None
    else:
        raise InputError(f"start must be 'random' or 'folded', got {start!r}", value=start)
    return random_problem(layout, kin, p.buffer if buffer is None else buffer, seed, near=near,
                          priority=priority, start=fixed, name=f"{p.name}-r{rings}-s{seed}", preset=p.name)


def _rings(preset: Preset, rings: int | None) -> int:
    """``rings`` as an ``int`` (``None``: the preset's whole focal plane), or a one-line error."""
    if rings is None:
        if preset.rings is None:
            raise InputError(f"preset {preset.name!r} has no whole focal plane in our sources: pass rings=...",
                             value=None)
        return preset.rings
    if isinstance(rings, bool) or not isinstance(rings, (int, np.integer)) or rings < 0:
        raise InputError(f"rings must be a non-negative integer, got {rings!r:.60}", value=rings)
    return int(rings)
