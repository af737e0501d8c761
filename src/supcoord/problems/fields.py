"""PROBLEM.json's fields: which the format knows, and one reader for each plain field.

The readers of ``collision`` (buffers, margins), ``layout.obstacles``, ``priority`` and
``preset`` turn decoded JSON into numbers and arrays; they know nothing of a
:class:`~supcoord.problems.problem.Problem`, which :func:`~supcoord.problems.problem.parse_problem`
builds from what they return.  Every reader raises a one-line
:class:`~supcoord.errors.FormatError` or :class:`~supcoord.errors.InputError` naming the
field and the value; :func:`unknown_fields` turns typos into warnings.
"""

from __future__ import annotations

import math

from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..geometry.presets_table import PRESETS
from ..geometry.kinematics import _is_int
from ..geometry.layout import _finite_number, _short
from .instrument import LAYOUT_FIELDS

__all__ = ["KNOWN_FIELDS", "EXTRA_FIELDS", "MAX_OBSTACLES", "apply_preset", "read_buffers", "read_margin",
           "read_obstacles", "read_priority", "unknown_fields"]

#: most fixed obstacles a layout may list
MAX_OBSTACLES = 100_000
#: top-level fields kept as they are (descriptive, or the preset that filled the file in)
EXTRA_FIELDS = ("name", "description", "comment", "preset", "seed")
#: every field of the format, by object (``kinematics`` by kind); keys starting with "_" are comments
KNOWN_FIELDS = {
    "": ("layout", "kinematics", "collision", "start", "target", "priority", "weight", "offline",
         "fibre") + EXTRA_FIELDS,
    "layout/hex": ("kind", "rings", "pitch"),
    "layout/points": ("kind", "xy", "obstacles"),
    "layout/instrument": LAYOUT_FIELDS,
    "kinematics/rotary": ("kind", "arm", "steps"),
    "kinematics/alpha-beta": ("kind", "alpha", "beta", "alpha_steps", "beta_steps", "beta_range", "alpha_range"),
    "collision": ("buffer", "margin", "obstacle_margin"),
}


def read_obstacles(layout: dict, where: str | None) -> tuple[np.ndarray, np.ndarray]:
    """``layout.obstacles``: ``[{"xy": [x, y], "buffer": r} | {"segment": [[x, y], [x, y]], "buffer": r}, ...]``."""
    spec = layout.get("obstacles", [])
    if not isinstance(spec, list) or len(spec) > MAX_OBSTACLES:
        raise FormatError(f"layout.obstacles must be a list of at most {MAX_OBSTACLES} objects, got {_short(spec)}",
                          value=spec, where=where)
    segs, bufs = [], []
    for i, o in enumerate(spec):
        field_name = f"layout.obstacles[{i}]"
        if not isinstance(o, dict) or set(o) - {"xy", "segment", "buffer"} or ("xy" in o) == ("segment" in o):
            raise FormatError(f"{field_name} must be {{\"xy\": [x, y], \"buffer\": r}} or {{\"segment\": [[x, y], "
                              f"[x, y]], \"buffer\": r}}, got {_short(o)}", value=o, where=where)
        pts = [o["xy"], o["xy"]] if "xy" in o else o["segment"]
        if not (isinstance(pts, list) and len(pts) == 2 and all(isinstance(q, list) and len(q) == 2 and
                                                                all(_finite_number(v) for v in q) for q in pts)):
            raise FormatError(f"{field_name}: a point is [x, y] in mm, got {_short(pts)}", value=pts, where=where)
        r = o.get("buffer", 0.0)
        if not _finite_number(r) or not 0 <= r <= 1e6:
            raise InputError(f"{field_name}.buffer must be in [0, 1e6] mm, got {_short(r)}", value=r, where=where)
        segs.append(pts)
        bufs.append(float(r))
    return np.array(segs, float).reshape(-1, 2, 2), np.array(bufs, float)


def read_buffers(spec: Any, n: int, where: str | None) -> np.ndarray:
    """``collision.buffer`` (mm): one number for every robot, or one per robot ``(N,)``."""
    if not isinstance(spec, dict) or "buffer" not in spec:
        raise FormatError(f"collision must be an object with a 'buffer' (mm), got {_short(spec)}", value=spec, where=where)
    buf = spec["buffer"]
    if _finite_number(buf):
        values = [buf]
    elif isinstance(buf, list) and len(buf) == n and all(_finite_number(v) for v in buf):
        values = buf
    else:
        raise FormatError(f"collision.buffer must be a number or a list of {n} numbers (mm), got {_short(buf)}",
                          value=buf, where=where)
    for v in values:
        if not 0 <= v <= 1e6:
            raise InputError(f"collision.buffer must be in [0, 1e6] mm, got {v}", value=v, where=where)
    return np.broadcast_to(np.asarray(values, float), (n,)).copy()


def read_margin(spec: Any, where: str | None, name: str = "margin", default: float = 0.0) -> float:
    """``collision.margin`` (mm, default 0): clearance asked for on top of the buffers;
    ``name="obstacle_margin"``: the same between robots and fixed obstacles (default: ``margin``)."""
    m = spec.get(name, default) if isinstance(spec, dict) else default
    if not _finite_number(m) or not 0 <= m <= 1e6:
        raise InputError(f"collision.{name} must be a number of mm in [0, 1e6], got {_short(m)}", value=m, where=where)
    return float(m)


def read_priority(value: Any, n: int, where: str | None) -> list[int]:
    """``priority``: one integer per robot, smaller first (default: the layout's order)."""
    if value is None:
        return list(range(1, n + 1))
    if not isinstance(value, list) or len(value) != n:
        got = f"{len(value)} entries" if isinstance(value, list) else _short(value)
        raise FormatError(f"priority must be a list of {n} integers (smaller = higher priority), got {got}",
                          value=value, where=where)
    for i, v in enumerate(value):
        if not _is_int(v):
            raise FormatError(f"priority[{i}] must be an integer, got {_short(v)}", value=v, where=where)
    return [int(v) for v in value]


def read_weight(value: Any, n: int, where: str | None) -> tuple[float, ...] | None:
    """``weight``: one finite number >= 0 per robot, what its target is worth (larger = more
    worth keeping on target when not every robot can reach its target), or None (absent)."""
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != n:
        got = f"{len(value)} entries" if isinstance(value, list) else _short(value)
        raise FormatError(f"weight must be a list of {n} numbers >= 0 (larger = more worth keeping on target), got "
                          f"{got}", value=value, where=where)
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            raise FormatError(f"weight[{i}] must be a finite number >= 0, got {_short(v)}", value=v, where=where)
    return tuple(float(v) for v in value)


def apply_preset(data: dict, where: str | None) -> dict:
    """``data`` with the preset's numbers filled in where the file leaves them out (module docstring)."""
    if "preset" not in data:
        return data
    name = data["preset"]
    if not isinstance(name, str) or name.lower() not in PRESETS:
        raise InputError(f"preset must be one of {', '.join(map(repr, PRESETS))}, got {_short(name)}",
                         value=name, where=where)
    pre = PRESETS[name.lower()]
    out = dict(data)
    layout = out.get("layout")
    if isinstance(layout, dict) and layout.get("kind") == "hex" and "pitch" not in layout:
        if pre.pitch is None:
            raise FormatError(f"layout.pitch is missing and preset {pre.name!r} has no pitch in our sources: "
                              f"give one (mm)", value=None, where=where)
        out["layout"] = dict(layout, pitch=pre.pitch)
    kin = out.get("kinematics", {})
    if isinstance(kin, dict):
        if kin.get("kind", "alpha-beta") != "alpha-beta":
            raise InputError(f"preset {pre.name!r} describes alpha-beta positioners, got kinematics.kind "
                             f"{_short(kin.get('kind'))}", value=kin.get("kind"), where=where)
        defaults = {"kind": "alpha-beta", "alpha": pre.alpha, "beta": pre.beta, "beta_range": list(pre.beta_range)}
        out["kinematics"] = dict(defaults, **kin)
    coll = out.get("collision", {})
    if isinstance(coll, dict):
        out["collision"] = dict({"buffer": pre.buffer}, **coll)
    return out


def unknown_fields(data: dict, where: str | None) -> list[str]:
    """One warning per field that :data:`KNOWN_FIELDS` does not list (``_comment`` keys excepted)."""
    prefix = f"{where}: " if where else ""
    objects = [("", data)]
    for key in ("layout", "kinematics"):
        if isinstance(data.get(key), dict):
            objects.append((f"{key}/{data[key].get('kind', 'alpha-beta')}", data[key]))
    if isinstance(data.get("collision"), dict):
        objects.append(("collision", data["collision"]))
    out = []
    for name, obj in objects:
        known = KNOWN_FIELDS[name]
        for key in obj:
            if key not in known and not str(key).startswith("_"):
                field_name = f"{name.split('/')[0]}.{key}" if name else str(key)
                out.append(f"{prefix}unknown field {field_name!r} ignored (known: {', '.join(known)})")
    return out
