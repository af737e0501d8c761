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
    """A random problem on a hex grid of ``rings`` rings of the preset instrument.

    ``start``: ``"random"`` or ``"folded"`` (every robot at :func:`folded_position`).
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
