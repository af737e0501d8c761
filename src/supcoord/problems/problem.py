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
:mod:`supcoord.geometry.presets_table`) fills in what the file leaves out: ``layout.pitch`` (hex layouts),
``kinematics.kind`` (``alpha-beta``), ``alpha``, ``beta``, ``beta_range``, and
``collision.buffer``; values given in the file win.  The discretisation
(``alpha_steps``, ``beta_steps``) is never implied, since it gives the positions their
meaning.

A :class:`Problem` is immutable once built: assigning an attribute raises
:class:`dataclasses.FrozenInstanceError` and its arrays are read-only, so nothing changes
it behind its caches; :func:`dataclasses.replace` makes a changed copy.
"""

from __future__ import annotations

import json
from dataclasses import FrozenInstanceError, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..outputs import atomic_write_text
from ..progress import summary_html, summary_repr
from ..geometry.collision import DEFAULT_TOL, CollisionTables, colliding_pairs, neighbour_pairs
from ..geometry.obstacles import held_tables, obstacle_motion_collides, rule_tables, unary_tables
from ..geometry.kinematics import Kinematics, kinematics_from_spec
from ..instruments import CollisionDefinition
from ..geometry.layout import _short, layout_from_spec
from ..geometry.segments import segment_distance
from .fields import (EXTRA_FIELDS, KNOWN_FIELDS, apply_preset, read_buffers, read_margin, read_obstacles,
                     read_priority, read_weight, unknown_fields)
from .instrument import definition_kept, instrument_collision, instrument_setup, problem_fibre
from .targets import parse_offline, parse_positions, radian_warnings, robot_lattices, with_angles
from .json_input import read_json
from .unlock import unlock_lattices, with_lattices

__all__ = ["Problem", "load_problem", "parse_problem", "read_json", "MAX_POSITIONERS", "MAX_PROBLEM_BYTES",
           "KNOWN_FIELDS"]

#: refuse problems bigger than this (a typo such as rings = 600 should not eat the memory)
MAX_POSITIONERS = 20_000
#: largest PROBLEM.json read (bytes): 20,000 positioners with every field take about 2 MB
MAX_PROBLEM_BYTES = 64 * 2**20


@dataclass(eq=False)
class Problem:
    """A validated coordination problem; positions are ``(N, J)`` int arrays.

    Immutable once built (module docstring): the dataclass's ``__init__`` sets the fields,
    after which an assignment raises; the lazily computed tables are kept by the methods
    that compute them.
    """

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
    #: the margin between robots and fixed obstacles (None: ``margin``), folded into
    #: :attr:`obstacle_buffers` (each grown by ``obstacle_margin − margin/2``)
    obstacle_margin: float | None = None
    #: robots held in place (offline): robot → its position; they never move
    held: dict[int, tuple[int, ...]] = field(default_factory=dict, repr=False)
    #: joint-space rules of the instrument: robot → ``(c0, c1)``, positions with commanded
    #: ``β < c0 + c1·α`` (degrees) are forbidden (kaiju's rule for robots beside a fiducial)
    joint_rules: dict[int, tuple[float, float]] = field(default_factory=dict, repr=False)
    _unary: dict | None = field(default=None, repr=False)
    #: the collision definition the buffers and margins are (an instrument's own, e.g. SDSS-V's
    #: ``"sdss-v kaiju"``), or ``None`` (the file's own numbers)
    collision_definition: CollisionDefinition | None = field(default=None, repr=False)
    #: what each robot's target is worth (``weight`` in PROBLEM.json), or None: every target alike
    weight: tuple[float, ...] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        # read-only arrays: nothing changes a problem in place behind its caches (.consistency)
        for name in ("bases", "buffers", "start", "target"):
            value = getattr(self, name)
            if isinstance(value, np.ndarray) and value.flags.writeable:
                value = value.copy()
                value.setflags(write=False)
                setattr(self, name, value)
        object.__setattr__(self, "_frozen", True)

    def __setattr__(self, name: str, value: Any) -> None:
        if self.__dict__.get("_frozen", False):
            raise FrozenInstanceError(f"a Problem is immutable: cannot set {name!r} (dataclasses.replace makes a "
                                      f"changed copy)")
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise FrozenInstanceError(f"a Problem is immutable: cannot delete {name!r}")

    def _keep(self, name: str, value: Any) -> Any:
        """Store the lazily computed cache ``name`` (``_pairs``, ``_tables``, ``_unary``) and return it."""
        object.__setattr__(self, name, value)
        return value

    @property
    def n(self) -> int:
        """Number of positioners."""
        return len(self.bases)

    def summary(self) -> dict[str, Any]:
        """What a notebook shows of the problem (its ``repr`` and HTML): name, instrument,
        positioners, kinematics and lattice, obstacles, robots held; never the arrays."""
        out: dict[str, Any] = {}
        for key, get in (("name", lambda: self.extra.get("name") or self.where),
                         ("layout", lambda: self.layout.get("name") or self.layout.get("kind")),
                         ("positioners", lambda: self.n),
                         ("kinematics", lambda: self.kinematics.kind),
                         ("lattice", lambda: " x ".join(map(str, self.kinematics.shape))),
                         ("obstacles", lambda: len(self.obstacles)),
                         ("held", lambda: len(self.held)),
                         ("margin_mm", lambda: self.margin)):
            try:
                value = get()
            except Exception:  # noqa: BLE001 - a repr shows what it can of a broken object
                value = "?"
            if value not in (None, 0, "") or key in ("positioners",):
                out[key] = value
        return out

    def __repr__(self) -> str:
        return summary_repr("Problem", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("Problem", self.summary())

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
        return self.tables().geometry_key(a, b)

    def pair_geometry_key(self, k: int) -> tuple:
        """:meth:`geometry_key` of the neighbour pair ``k`` (:attr:`pairs`), computed once per pair."""
        keys = self.__dict__.setdefault("_pair_geometry_keys", {})
        key = keys.get(k)
        if key is None:
            a, b = self.pairs[k]
            key = keys[k] = self.geometry_key(int(a), int(b))
        return key

    @property
    def pairs(self) -> np.ndarray:
        """Neighbour pairs ``(a, b)``, ``a < b`` (:func:`~supcoord.geometry.collision.neighbour_pairs`)."""
        if self._pairs is None:
            return self._keep("_pairs", neighbour_pairs(self.bases, self.reaches, self.buffers))
        return self._pairs

    def tables(self) -> CollisionTables:
        """The (lazily computed) static and swept tables of all neighbour pairs, shared by
        offset between pairs of identical robots, with every robot's :meth:`unary` tables
        folded in."""
        if self._tables is None:
            return self._keep("_tables", CollisionTables(self.kinematics, self.bases, self.buffers,
                                                         kins=self.robot_kinematics, unary=self.unary()))
        return self._tables

    def unary(self) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        """``p → (U, V)`` for every robot near a fixed obstacle, under a joint rule or held in
        place (:mod:`supcoord.geometry.obstacles`): positions and single moves refused
        whatever the other robots do."""
        if self._unary is None:
            out: dict[int, tuple[np.ndarray, np.ndarray]] = {}
            for p in range(self.n):
                t = self.own_tables(p, self.kin(p))
                if t is not None:
                    out[p] = t
            return self._keep("_unary", out)
        return self._unary

    def own_tables(self, p: int, kin: Kinematics) -> tuple[np.ndarray, np.ndarray] | None:
        """Robot ``p``'s :meth:`unary` tables ``(U, V)`` were its kinematics ``kin`` (None: it
        has no obstacle near, no joint rule and is not held)."""
        parts = []
        if len(self.obstacles):
            t = unary_tables(kin, self.bases[p], float(self.buffers[p]), self.obstacles, self.obstacle_buffers)
            if t is not None:
                parts.append(t)
        if p in self.joint_rules:
            parts.append(rule_tables(kin, *self.joint_rules[p]))
        if p in self.held:
            parts.append(held_tables(kin, self.held[p]))
        if not parts:
            return None
        return np.logical_or.reduce([u for u, _ in parts]), np.logical_or.reduce([v for _, v in parts])

    def own_motion_blocked(self, p: int, q0: Any, delta: Any, tol: float | None = None) -> np.ndarray:
        """Is robot ``p``'s motion ``q0 + t·delta`` (``(E, J)``, several joints at once) refused
        by its :meth:`unary` constraints (held, a joint rule or an obstacle on the way)?"""
        q0 = np.atleast_2d(np.asarray(q0, dtype=np.int64))
        delta = np.broadcast_to(np.atleast_2d(np.asarray(delta, dtype=np.int64)), q0.shape)
        if p not in self.unary():
            return np.zeros(len(q0), dtype=bool)
        kin = self.kin(p)
        end = kin.wrap(q0 + delta)
        ok = kin.in_range(end)
        U = self.unary()[p][0]
        hit = ~ok
        hit[ok] = U[kin.flat_index(q0[ok])] | U[kin.flat_index(end[ok])]
        if p in self.held:
            hit |= np.any(delta != 0, axis=1)
        todo = np.nonzero(~hit)[0]
        if len(todo) and len(self.obstacles):
            hit[todo] = obstacle_motion_collides(kin, self.bases[p], q0[todo], delta[todo], float(self.buffers[p]),
                                                 self.obstacles, self.obstacle_buffers,
                                                 DEFAULT_TOL if tol is None else tol)
        return hit

    def collisions(self, positions: Any) -> list[tuple[int, int, float]]:
        """Colliding pairs ``(a, b, distance)`` of a configuration ``(N, J)``."""
        return colliding_pairs(self.kins, self.bases, self.buffers, positions, self.pairs)

    def at_target(self, positions: Any) -> np.ndarray:
        return np.all(np.asarray(positions) == self.target, axis=-1)

    def collision_statement(self) -> dict:
        """PLAN.json's ``collision``: the definition the plan was made and checked under
        (``definition``: the instrument's name for it, or ``"problem"``), its robot buffer,
        margin between robots and margin to fixed obstacles (mm)."""
        if self.collision_definition is not None:
            return self.collision_definition.to_json()
        buf = self.buffers - self.margin / 2
        om = self.margin if self.obstacle_margin is None else self.obstacle_margin
        return {"definition": "problem",
                "buffer_mm": float(buf[0]) if len(buf) and np.all(buf == buf[0]) else [float(v) for v in buf],
                "margin_mm": float(self.margin), "obstacle_margin_mm": float(om)}

    def to_json(self) -> dict:
        buf = self.buffers - self.margin / 2
        buffer: Any = float(buf[0]) if np.all(buf == buf[0]) else [float(v) for v in buf]
        if self.collision_definition is not None:  # its own numbers, not re-derived ones
            buffer = self.collision_definition.buffer_mm
        collision: dict[str, Any] = {"buffer": buffer}
        if self.margin:
            collision["margin"] = self.margin
        if self.obstacle_margin is not None and self.obstacle_margin != self.margin:
            collision["obstacle_margin"] = self.obstacle_margin
        out = dict(self.extra)
        kinematics = self.kinematics.to_json()
        if self.layout.get("kind") == "instrument":  # the arms are the instrument's, measured per robot
            kinematics = {k: v for k, v in kinematics.items() if k not in ("alpha", "beta")}
        out.update({"layout": self.layout, "kinematics": kinematics, "collision": collision})
        for name, conf in (("start", self.start), ("target", self.target)):
            if self.robot_kinematics is None:
                out[name] = [self.kinematics.position_to_json(q) for q in conf]
            else:  # the exact angles each robot's lattice holds
                ang = self.angles_deg(conf)
                if self.kinematics.joints[0].wraps:
                    ang[..., 0] %= 360.0
                out[name] = {"alpha_beta_deg": ang.tolist()}
        out["priority"] = [int(p) for p in self.priority]
        if self.weight is not None:
            out["weight"] = [float(w) for w in self.weight]
        if self.held:
            ang = self.angles_deg(self.start)
            out["offline"] = {str(p): [float(v) for v in ang[p]] for p in sorted(self.held)}
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


def load_problem(path: str | Path, check_collisions: bool = True) -> Problem:
    """Read and validate a PROBLEM.json file (errors carry ``where = path``); at most
    :data:`MAX_PROBLEM_BYTES`."""
    return parse_problem(read_json(path, "problem", MAX_PROBLEM_BYTES), str(path), check_collisions)


def parse_problem(data: Any, where: str | None = None, check_collisions: bool = True) -> Problem:
    """Validate a decoded PROBLEM.json object into a :class:`Problem`.

    Parameters
    ----------
    data : dict
        The decoded PROBLEM.json (``docs/formats.md``): ``layout`` (bases in mm),
        ``kinematics`` (arm lengths in mm, lattice steps), ``collision`` (buffers and margins
        in mm), ``start`` and ``target`` (lattice indices, joint angles in degrees or fibre
        positions in mm), and the optional ``priority``, ``offline``, ``fibre``, ``preset``.
    where : str, optional
        Where the data came from (a file name), named by every error.
    check_collisions : bool, default True
        Refuse a start or target whose robots collide with each other, a fixed obstacle or
        a joint rule.

    Returns
    -------
    Problem
        The problem, immutable; fields the format does not know are listed in its
        ``warnings``.

    Raises
    ------
    FormatError
        A field of the wrong type or shape.
    InputError
        A value out of range or a colliding start or target; an error about angles that
        look like radians says so (:func:`~.targets.radian_warnings`).

    Examples
    --------
    >>> p = parse_problem({"layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [0] * 7, "target": [6] * 7})
    >>> p.n, p.kinematics.shape, float(p.buffers[0])
    (7, (12,), 2.0)
    >>> parse_problem({"layout": {"kind": "hex", "rings": 1, "pitch": 22.4}})
    Traceback (most recent call last):
    ...
    supcoord.errors.FormatError: required field 'kinematics' is missing

    References
    ----------
    The PROBLEM.json format: ``docs/formats.md``.
    """
    try:
        return _parse_problem(data, where, check_collisions)
    except InputError as exc:
        hint = radian_warnings(data, None) if type(exc) is InputError else []
        if not hint:
            raise
        raise InputError(f"{exc.message} ({hint[0]})", value=exc.value, where=exc.where) from None


def _parse_problem(data: Any, where: str | None, check_collisions: bool) -> Problem:
    if not isinstance(data, dict):
        raise FormatError(f"a problem must be a JSON object, got {_short(data)}", value=data, where=where)
    data = apply_preset(data, where)
    layout_spec = data.get("layout")
    instrument = isinstance(layout_spec, dict) and layout_spec.get("kind") == "instrument"
    for key in ("layout", "start", "target") if instrument else ("layout", "kinematics", "collision", "start", "target"):
        if key not in data:
            raise FormatError(f"required field '{key}' is missing", value=None, where=where)
    fibre = problem_fibre(data, where)  # one fibre, wherever it is named
    if fibre is not None:
        layout_spec = dict(layout_spec, fibre=fibre)
    setup = instrument_setup(layout_spec, data, where) if instrument else None
    bases = setup.bases if setup else layout_from_spec(layout_spec, where)
    n = len(bases)
    if n > MAX_POSITIONERS:
        raise InputError(f"layout has {n} positioners, more than the supported {MAX_POSITIONERS}", value=n, where=where)
    kin = setup.kinematics if setup else kinematics_from_spec(data["kinematics"], where)
    collision = data.get("collision", {} if setup else None)
    if setup and isinstance(collision, dict):  # the instrument's own definition where the file is silent
        collision = instrument_collision(setup, collision)
    buffers = read_buffers(collision, n, where)
    margin = read_margin(collision, where)
    obstacle_margin = read_margin(collision, where, "obstacle_margin", margin)
    start, target, held, robot_kins = _positions(data, kin, bases, setup.robots if setup else None, where)
    if setup:
        obstacles, obstacle_buffers = setup.obstacles, setup.obstacle_buffers
    else:
        obstacles, obstacle_buffers = read_obstacles(layout_spec, where)
    priority = read_priority(data.get("priority"), n, where)
    layout = setup.layout if setup else _layout_json(layout_spec, bases, obstacles, obstacle_buffers)
    extra = {k: v for k, v in data.items() if k in EXTRA_FIELDS}
    problem = Problem(layout, kin, bases, buffers + margin / 2, start, target, priority, where, extra,
                      unknown_fields(data, where) + radian_warnings(data, where), robot_kinematics=robot_kins,
                      margin=margin,
                      obstacles=obstacles, obstacle_buffers=obstacle_buffers + (obstacle_margin - margin / 2),
                      obstacle_margin=obstacle_margin,
                      held={p: tuple(int(v) for v in start[p]) for p in held},
                      joint_rules=setup.joint_rules if setup else {},
                      collision_definition=definition_kept(setup, buffers, margin, obstacle_margin) if setup else None,
                      weight=read_weight(data.get("weight"), n, where))
    # robots their obstacles would lock in on a coarse lattice get a finer one (.unlock)
    problem = with_lattices(problem, unlock_lattices(problem))
    if check_collisions:
        for name, conf in (("start", problem.start), ("target", problem.target)):
            _check_free(problem, name, conf, where)
    return problem


def _positions(data: dict, kin: Kinematics, bases: np.ndarray, base_kins: list[Kinematics] | None,
               where: str | None) -> tuple[np.ndarray, np.ndarray, dict, list[Kinematics] | None]:
    """``start``, ``target`` (positions ``(N, J)``), the offline robots and the robots' own
    kinematics (lattices holding exact angles where the file gives angles)."""
    n = len(bases)
    start = parse_positions(data["start"], "start", n, kin, bases, where, base_kins)
    target = parse_positions(data["target"], "target", n, kin, bases, where, base_kins)
    held = parse_offline(data.get("offline"), n, kin, where, base_kins)
    if held:  # an offline robot stands at its angles from start to target
        start, target = (with_angles(c, held, kin, base_kins) for c in (start, target))
    robot_kins = base_kins
    if not (isinstance(start, np.ndarray) and isinstance(target, np.ndarray)):
        try:
            robot_kins, start, target = robot_lattices(kin, start, target, base_kins)  # type: ignore[arg-type]
        except InputError as exc:
            raise InputError(exc.message, value=exc.value, where=where) from None
    return start, target, held, robot_kins


def _layout_json(layout_spec: dict, bases: np.ndarray, obstacles: np.ndarray, obstacle_buffers: np.ndarray) -> dict:
    """PROBLEM.json's ``layout`` as the problem keeps it: a hex grid's numbers, or the points
    and their obstacles."""
    if layout_spec.get("kind") != "points":
        return {"kind": "hex", "rings": int(layout_spec["rings"]), "pitch": float(layout_spec["pitch"])}
    layout: dict[str, Any] = {"kind": "points", "xy": bases.tolist()}
    if len(obstacles):
        layout["obstacles"] = [{"xy": o[0].tolist(), "buffer": float(r)} if np.array_equal(o[0], o[1]) else
                               {"segment": o.tolist(), "buffer": float(r)} for o, r in zip(obstacles, obstacle_buffers)]
    return layout


def _check_free(problem: Problem, name: str, conf: np.ndarray, where: str | None) -> None:
    """A start or target where robots collide, touch an obstacle or break a joint rule: one
    line naming them."""
    hits = problem.collisions(conf)
    if hits:
        a, b, d = hits[0]
        more = f" (and {len(hits) - 1} more colliding pairs)" if len(hits) > 1 else ""
        raise InputError(
            f"{name} configuration collides: positioners {a} and {b} are {d:.3f} mm apart, "
            f"less than their buffers' sum {problem.buffers[a] + problem.buffers[b]:.3f} mm{more}",
            value=[a, b], where=where)
    _check_fixed(problem, name, conf, where)


def _check_fixed(problem: Problem, name: str, conf: np.ndarray, where: str | None) -> None:
    """A start or target touching an obstacle or breaking a joint rule: one line naming both."""
    for p, (U, _) in problem.unary().items():
        if p in problem.held or not U[int(problem.kin(p).flat_index(conf[p]))]:
            continue
        seg = problem.kin(p).segments(conf[p].astype(float)) + problem.bases[p]
        if len(problem.obstacles):
            d = segment_distance(np.broadcast_to(seg[0], (len(problem.obstacles), 2)),
                                 np.broadcast_to(seg[1], (len(problem.obstacles), 2)),
                                 problem.obstacles[:, 0], problem.obstacles[:, 1])
            gap = d - problem.buffers[p] - problem.obstacle_buffers
            o = int(np.argmin(gap))
            if gap[o] < 0:
                raise InputError(f"{name}: robot {p} is {d[o]:.3f} mm from obstacle {o}, less than their buffers' sum "
                                 f"{problem.buffers[p] + problem.obstacle_buffers[o]:.3f} mm", value=[p, o], where=where)
        a, b = problem.angles_deg(conf)[p]
        raise InputError(f"{name}: robot {p} at alpha {a:.3f}, beta {b:.3f} deg breaks the instrument's joint rule "
                         f"(beta < {problem.joint_rules[p][0]:g} + {problem.joint_rules[p][1]:g}·alpha is refused)",
                         value=[p, a, b], where=where)
