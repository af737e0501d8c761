"""PROBLEM.json ↔ :class:`Problem`: a geometric coordination problem, validated.

A problem is ``(layout, kinematics, buffers, start, target, priority)`` (``docs/formats.md``):
positioner ``p`` has base ``x_p`` (the layout's order), positions ``q ∈ Q`` (the
kinematics' discrete positions), buffer ``r_p``; ``start``/``target`` give one position
per positioner, each a collision-free configuration::

    ∀ (a, b) neighbours.  dist(S_a(start_a), S_b(start_b)) ≥ r_a + r_b   (and the same for target)

Every user mistake raises :class:`~supcoord.errors.FormatError` (wrong type/shape) or
:class:`~supcoord.errors.InputError` (bad value, colliding start/target) with
``where`` = the file and a message naming the field and value.  A field the format
does not know (a typo such as ``"prority"``) is not an error but is reported in
:attr:`Problem.warnings`, which the command line prints on standard error.

An optional top-level ``"preset"`` (``"sdss-v"``, ``"desi"``, ``"moons"``, ``"pfs"``;
:mod:`supcoord.geometry.instruments`) fills in what the file leaves out: ``layout.pitch`` (hex layouts),
``kinematics.kind`` (``alpha-beta``), ``alpha``, ``beta``, ``beta_range``, and
``collision.buffer``; values given in the file win.  The discretisation
(``alpha_steps``, ``beta_steps``) is never implied, since it gives the positions their
meaning.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..outputs import atomic_write_text
from ..geometry.collision import CollisionTables, colliding_pairs, neighbour_pairs
from ..geometry.instruments import PRESETS
from ..geometry.kinematics import Kinematics, _is_int, kinematics_from_spec
from ..geometry.layout import _finite_number, _short, layout_from_spec
from .targets import parse_positions, robot_lattices

__all__ = ["Problem", "load_problem", "parse_problem", "read_json", "MAX_POSITIONERS", "MAX_PROBLEM_BYTES",
           "KNOWN_FIELDS"]

#: refuse problems bigger than this (a typo such as rings = 600 should not eat the memory)
MAX_POSITIONERS = 20_000
#: largest PROBLEM.json read (bytes): 20,000 positioners with every field take about 2 MB
MAX_PROBLEM_BYTES = 64 * 2**20
#: top-level fields kept as they are (descriptive, or the preset that filled the file in)
EXTRA_FIELDS = ("name", "description", "comment", "preset", "seed")
#: every field of the format, by object (``kinematics`` by kind); keys starting with "_" are comments
KNOWN_FIELDS = {
    "": ("layout", "kinematics", "collision", "start", "target", "priority") + EXTRA_FIELDS,
    "layout/hex": ("kind", "rings", "pitch"),
    "layout/points": ("kind", "xy"),
    "kinematics/rotary": ("kind", "arm", "steps"),
    "kinematics/alpha-beta": ("kind", "alpha", "beta", "alpha_steps", "beta_steps", "beta_range", "alpha_range"),
    "collision": ("buffer", "margin"),
}


@dataclass(eq=False)
class Problem:
    """A validated coordination problem; positions are ``(N, J)`` int arrays."""

    layout: dict
    kinematics: Kinematics
    bases: np.ndarray
    buffers: np.ndarray
    start: np.ndarray
    target: np.ndarray
    priority: list[int]
    where: str | None = None
    extra: dict = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    _tables: CollisionTables | None = field(default=None, repr=False)
    _pairs: np.ndarray | None = field(default=None, repr=False)
    #: per-robot kinematics (each robot's own lattice and arms), ``None``: every robot is ``kinematics``
    robot_kinematics: list[Kinematics] | None = field(default=None, repr=False)
    #: fixed obstacles: segments ``(M, 2, 2)`` in the focal plane (mm; a point is a zero-length
    #: segment) and their buffers ``(M,)``; a robot collides with one when
    #: ``dist(S_p, O) < r_p + r_O``
    obstacles: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)), repr=False)
    obstacle_buffers: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    #: the clearance margin (mm) the user asked for on top of the buffers: every pair needs
    #: ``dist ≥ r_a + r_b + margin``, folded into :attr:`buffers` (each grown by ``margin/2``)
    margin: float = 0.0

    @property
    def n(self) -> int:
        """Number of positioners."""
        return len(self.bases)

    def kin(self, p: int) -> Kinematics:
        """The kinematics of robot ``p``: its own lattice and arms where it has them, else
        :attr:`kinematics` (which always holds the joints, steps and moves every robot shares)."""
        return self.kinematics if self.robot_kinematics is None else self.robot_kinematics[p]

    @property
    def kins(self) -> Kinematics | list[Kinematics]:
        """:attr:`kinematics` when every robot shares it, else the list of robots' kinematics."""
        return self.kinematics if self.robot_kinematics is None else self.robot_kinematics

    @property
    def reaches(self) -> np.ndarray:
        """Per robot, the farthest point of its colliding segment from its base (mm)."""
        if self.robot_kinematics is None:
            return np.full(self.n, self.kinematics.reach)
        return np.array([k.reach for k in self.robot_kinematics], dtype=float)

    def angles_deg(self, positions: Any) -> np.ndarray:
        """Joint angles in degrees of (fractional) positions ``(..., N, J)``: each robot's own."""
        q = np.asarray(positions, dtype=float)
        if self.robot_kinematics is None:
            return self.kinematics.joint_angles_deg(q)
        out = np.empty(q.shape)
        for p, k in enumerate(self.robot_kinematics):
            out[..., p, :] = k.joint_angles_deg(q[..., p, :])
        return out

    def geometry_key(self, a: int, b: int) -> tuple:
        """What the collision geometry of robots ``a`` and ``b`` depends on: their offset, buffer
        sum and kinematics (:meth:`CollisionTables`' sharing key); equal keys, equal tables."""
        off = np.round(self.bases[b] - self.bases[a], 9) + 0.0
        ids = self.tables()._ids
        return (float(off[0]), float(off[1]), round(float(self.buffers[a] + self.buffers[b]), 9), int(ids[a]),
                int(ids[b]))

    @property
    def pairs(self) -> np.ndarray:
        """Neighbour pairs ``(a, b)``, ``a < b`` (:func:`~supcoord.geometry.collision.neighbour_pairs`)."""
        if self._pairs is None:
            self._pairs = neighbour_pairs(self.bases, self.reaches, self.buffers)
        return self._pairs

    def tables(self) -> CollisionTables:
        """The (lazily computed) static and swept tables of all neighbour pairs, shared by
        offset between pairs of identical robots."""
        if self._tables is None:
            self._tables = CollisionTables(self.kinematics, self.bases, self.buffers, kins=self.robot_kinematics)
        return self._tables

    def collisions(self, positions: Any) -> list[tuple[int, int, float]]:
        """Colliding pairs ``(a, b, distance)`` of a configuration ``(N, J)``."""
        return colliding_pairs(self.kins, self.bases, self.buffers, positions, self.pairs)

    def at_target(self, positions: Any) -> np.ndarray:
        return np.all(np.asarray(positions) == self.target, axis=-1)

    def to_json(self) -> dict:
        buf = self.buffers - self.margin / 2
        buffer: Any = float(buf[0]) if np.all(buf == buf[0]) else [float(v) for v in buf]
        collision: dict[str, Any] = {"buffer": buffer}
        if self.margin:
            collision["margin"] = self.margin
        out = dict(self.extra)
        out.update({"layout": self.layout, "kinematics": self.kinematics.to_json(), "collision": collision})
        for name, conf in (("start", self.start), ("target", self.target)):
            if self.robot_kinematics is None:
                out[name] = [self.kinematics.position_to_json(q) for q in conf]
            else:  # the exact angles each robot's lattice holds
                ang = self.angles_deg(conf)
                if self.kinematics.joints[0].wraps:
                    ang[..., 0] %= 360.0
                out[name] = {"alpha_beta_deg": ang.tolist()}
        out["priority"] = [int(p) for p in self.priority]
        return out

    def dump(self, path: str | Path) -> None:
        """Write PROBLEM.json atomically (:func:`supcoord.outputs.atomic_write_text`)."""
        atomic_write_text(path, json.dumps(self.to_json(), indent=1) + "\n")

    @classmethod
    def from_json(cls, data: Any, where: str | None = None, check_collisions: bool = True) -> "Problem":
        return parse_problem(data, where, check_collisions)

    @classmethod
    def load(cls, path: str | Path) -> "Problem":
        return load_problem(path)


def read_json(path: str | Path, what: str, max_bytes: int) -> Any:
    """Decode a JSON file, bounded: refused (one-line :class:`InputError`/:class:`FormatError`
    with ``where = path``) when missing, not a regular file, over ``max_bytes``, not UTF-8,
    not JSON, nested too deeply, or holding an integer too long to convert (Python's limit of
    4,300 digits)."""
    where = str(path)
    p = Path(path)
    if not p.exists():
        raise InputError(f"{what} file not found", value=where, where=where)
    if not p.is_file():
        raise InputError(f"is not a regular file (a directory, FIFO or device), not a {what} file", value=where,
                         where=where)
    size = p.stat().st_size
    if size > max_bytes:
        raise InputError(f"{what} file is {size} bytes, more than the {max_bytes} a {what} may have", value=size,
                         where=where)
    try:
        with open(p, "rb") as f:
            raw = f.read(max_bytes + 1)
        if len(raw) > max_bytes:
            raise InputError(f"{what} file is more than {max_bytes} bytes", value=len(raw), where=where)
        return json.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise FormatError(f"not a UTF-8 text file ({exc.reason})", value=where, where=where) from None
    except json.JSONDecodeError as exc:
        raise FormatError(f"not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}",
                          value=where, where=where) from None
    except RecursionError:
        raise FormatError("JSON nested too deeply", value=where, where=where) from None
    except ValueError as exc:  # e.g. "Exceeds the limit (4300 digits) for integer string conversion"
        raise FormatError(f"a number is out of range: {str(exc).splitlines()[0]}", value=where, where=where) from None
    except OSError as exc:
        raise InputError(f"cannot be read: {exc.strerror or exc}", value=where, where=where) from None


def load_problem(path: str | Path, check_collisions: bool = True) -> Problem:
    """Read and validate a PROBLEM.json file (errors carry ``where = path``); at most
    :data:`MAX_PROBLEM_BYTES`."""
    return parse_problem(read_json(path, "problem", MAX_PROBLEM_BYTES), str(path), check_collisions)


def parse_problem(data: Any, where: str | None = None, check_collisions: bool = True) -> Problem:
    """Validate a PROBLEM.json object (already decoded) into a :class:`Problem`."""
    if not isinstance(data, dict):
        raise FormatError(f"a problem must be a JSON object, got {_short(data)}", value=data, where=where)
    data = _apply_preset(data, where)
    for key in ("layout", "kinematics", "collision", "start", "target"):
        if key not in data:
            raise FormatError(f"required field '{key}' is missing", value=None, where=where)
    bases = layout_from_spec(data["layout"], where)
    n = len(bases)
    if n > MAX_POSITIONERS:
        raise InputError(f"layout has {n} positioners, more than the supported {MAX_POSITIONERS}", value=n, where=where)
    kin = kinematics_from_spec(data["kinematics"], where)
    buffers = _buffers(data["collision"], n, where)
    margin = _margin(data["collision"], where)
    start = parse_positions(data["start"], "start", n, kin, bases, where)
    target = parse_positions(data["target"], "target", n, kin, bases, where)
    robot_kins = None
    if not (isinstance(start, np.ndarray) and isinstance(target, np.ndarray)):
        try:
            robot_kins, start, target = robot_lattices(kin, start, target)  # type: ignore[arg-type]
        except InputError as exc:
            raise InputError(exc.message, value=exc.value, where=where) from None
    for name in ("offline",):
        if name in data:
            raise InputError(f"field '{name}' (robots fixed in place) is not supported by this version: leave it out "
                             f"and give those robots' start and target equal", value=name, where=where)
    if isinstance(data["layout"], dict) and "obstacles" in data["layout"]:
        raise InputError("layout.obstacles (fixed obstacles) is not supported by this version", value="obstacles",
                         where=where)
    priority = _priority(data.get("priority"), n, where)
    layout = dict(data["layout"])
    if layout.get("kind") == "points":
        layout = {"kind": "points", "xy": bases.tolist()}
    else:
        layout = {"kind": "hex", "rings": int(layout["rings"]), "pitch": float(layout["pitch"])}
    extra = {k: v for k, v in data.items() if k in EXTRA_FIELDS}
    problem = Problem(layout, kin, bases, buffers + margin / 2, start, target, priority, where, extra,
                      _unknown_fields(data, where), robot_kinematics=robot_kins, margin=margin)
    if check_collisions:
        for name, conf in (("start", start), ("target", target)):
            hits = problem.collisions(conf)
            if hits:
                a, b, d = hits[0]
                more = f" (and {len(hits) - 1} more colliding pairs)" if len(hits) > 1 else ""
                raise InputError(
                    f"{name} configuration collides: positioners {a} and {b} are {d:.3f} mm apart, "
                    f"less than their buffers' sum {problem.buffers[a] + problem.buffers[b]:.3f} mm{more}",
                    value=[a, b], where=where)
    return problem


def _buffers(spec: Any, n: int, where: str | None) -> np.ndarray:
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


def _margin(spec: Any, where: str | None) -> float:
    """``collision.margin`` (mm, default 0): clearance asked for on top of the buffers."""
    m = spec.get("margin", 0.0) if isinstance(spec, dict) else 0.0
    if not _finite_number(m) or not 0 <= m <= 1e6:
        raise InputError(f"collision.margin must be a number of mm in [0, 1e6], got {_short(m)}", value=m, where=where)
    return float(m)


def _priority(value: Any, n: int, where: str | None) -> list[int]:
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


def _apply_preset(data: dict, where: str | None) -> dict:
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


def _unknown_fields(data: dict, where: str | None) -> list[str]:
    """One warning per field that :data:`KNOWN_FIELDS` does not list (``_comment`` keys excepted)."""
    prefix = f"{where}: " if where else ""
    objects = [("", data)]
    for key in ("layout", "kinematics"):
        objects.append((f"{key}/{data[key].get('kind')}", data[key]))
    objects.append(("collision", data["collision"]))
    out = []
    for name, obj in objects:
        known = KNOWN_FIELDS[name]
        for key in obj:
            if key not in known and not str(key).startswith("_"):
                field_name = f"{name.split('/')[0]}.{key}" if name else str(key)
                out.append(f"{prefix}unknown field {field_name!r} ignored (known: {', '.join(known)})")
    return out
