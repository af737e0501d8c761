"""Random problems on an instrument's geometry (a hex grid of the preset's pitch and arms).

The instrument numbers live in :mod:`supcoord.geometry.presets_table`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..geometry.presets_table import folded_position, get_preset, preset_kinematics
from .problem import Problem
from .random import random_problem

__all__ = ["preset_problem"]


def preset_problem(name: str, rings: int = 2, seed: int = 0, *, alpha_steps: int = 36, beta_steps: int = 19,
                   pitch: float | None = None, buffer: float | None = None, start: str = "random",
                   near: int | None = None, priority: str = "random") -> Problem:
    """A random problem on a hex grid of ``rings`` rings of a preset instrument's geometry.

    Parameters
    ----------
    name : str
        The preset: ``"sdss-v"``, ``"desi"``, ``"moons"`` or ``"pfs"`` (case-insensitive).
    rings : int, default 2
        Rings of the hex grid around the centre robot (``1 + 3·R·(R+1)`` robots).
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
        An unknown preset, no pitch for a preset without one, an unknown ``start``, or
        arguments :func:`~supcoord.problems.random.random_problem` refuses.

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
    kin = preset_kinematics(name, alpha_steps, beta_steps)
    layout = {"kind": "hex", "rings": int(rings), "pitch": float(pitch)}
    n = 1 + 3 * int(rings) * (int(rings) + 1)
    if start == "folded":
        fixed = np.tile(folded_position(kin), (n, 1))
    elif start == "random":
        fixed = None
    else:
        raise InputError(f"start must be 'random' or 'folded', got {start!r}", value=start)
    return random_problem(layout, kin, p.buffer if buffer is None else buffer, seed, near=near,
                          priority=priority, start=fixed, name=f"{p.name}-r{rings}-s{seed}", preset=p.name)
