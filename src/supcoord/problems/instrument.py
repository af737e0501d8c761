"""Real focal planes as PROBLEM.json layouts: ``{"kind": "instrument", "name": ...}``.

``sdss-v-apo`` and ``sdss-v-lco`` are SDSS-V's measured woks (:mod:`supcoord.instruments`,
``docs/instruments.md``): 500 robots in the calibration table's row order, each with its
own base, measured alpha arm, calibration offsets and fibres; the beta arm's collision
segment and buffer, the fiducials and guide cameras as fixed obstacles with their buffers,
and kaiju's joint rule for robots beside a fiducial, all as SDSS-V's planner kaiju has them.
``kinematics`` and ``collision`` may be omitted: then the joints have the instrument's hard
stops (alpha [0°, 360°], beta [0°, 180°], where SDSS-V operates its targets) and
:data:`DEFAULT_STEPS` positions; given, they may set ``alpha_steps``, ``beta_steps``,
``alpha_range``, ``beta_range`` and ``collision.buffer``/``margin``/``obstacle_margin``, never
the arm lengths, which are measured per robot.  ``collision`` defaults to the instrument's own
definition (:func:`supcoord.instruments.collision_definition`; SDSS-V: kaiju's, buffer 2.0 mm,
margin 0.0782 mm between robots, none to obstacles), so that a plan passes the instrument's
own check; a ``margin`` given without ``obstacle_margin`` applies to both, as elsewhere.  ``"fibre"`` (default ``"boss"``) chooses the fibre that
``xy_mm`` targets place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..geometry.kinematics import AlphaBeta
from ..geometry.layout import _short
from ..instruments import INSTRUMENTS, CollisionDefinition, collision_definition, load_instrument

__all__ = ["DEFAULT_STEPS", "InstrumentSetup", "definition_kept", "instrument_collision", "instrument_setup",
           "LAYOUT_FIELDS"]

#: default discretisation of an instrument's joints (alpha, beta): 30° steps, chosen by
#: measurement on the APO wok unfolding to kaiju's random targets (seed 0;
#: ``benchmarks/bench_instrument.py``): 13 × 7 planned it in 82 s and 1.1 GB, 19 × 10 in 150 s
#: and 3.7 GB with the same motion time (73 s vs 71 s at 12°/s); 37 × 19 needs more memory than
#: a 24 GiB machine has (every robot's own lattice makes every pair's tables its own)
DEFAULT_STEPS = (13, 7)
LAYOUT_FIELDS = ("kind", "name", "fibre")
_KIN_FIELDS = ("kind", "alpha_steps", "beta_steps", "alpha_range", "beta_range")


@dataclass
class InstrumentSetup:
    """What an instrument layout fills in: bases, each robot's kinematics, obstacles, rules."""

    layout: dict
    kinematics: AlphaBeta          # the shared index structure (nominal arms)
    robots: list[AlphaBeta]         # each robot's own
    bases: np.ndarray
    buffer: float
    obstacles: np.ndarray
    obstacle_buffers: np.ndarray
    joint_rules: dict[int, tuple[float, float]]
    #: the instrument's own collision definition, the default of ``collision``
    collision: CollisionDefinition


def instrument_setup(layout: dict, data: dict, where: str | None) -> InstrumentSetup:
    """Read an instrument layout (module docstring); errors name the field and value."""
    unknown = sorted(set(layout) - set(LAYOUT_FIELDS))
    if unknown:
        raise FormatError(f"layout.{unknown[0]} is not a field of an instrument layout (known: "
                          f"{', '.join(LAYOUT_FIELDS)})", value=unknown[0], where=where)
    name = layout.get("name")
    if not isinstance(name, str) or name not in INSTRUMENTS:
        raise InputError(f"layout.name: unknown instrument {_short(name)} (known: {', '.join(INSTRUMENTS)})",
                         value=name, where=where)
    geom = load_instrument(name)
    fibre = layout.get("fibre", "boss")
    if not isinstance(fibre, str) or fibre not in geom.fibres:  # a list or object is no fibre's name
        raise InputError(f"layout.fibre must be one of {', '.join(geom.fibres)}, got {_short(fibre)}", value=fibre,
                         where=where)
    spec = data.get("kinematics", {})
    if not isinstance(spec, dict):
        raise FormatError(f"kinematics must be an object, got {_short(spec)}", value=spec, where=where)
    for key in spec:
        if key not in _KIN_FIELDS and not str(key).startswith("_"):
            raise InputError(f"kinematics.{key} cannot be set for instrument {name!r}: its robots are measured (only "
                             f"{', '.join(_KIN_FIELDS[1:])} may be given)", value=key, where=where)
    if spec.get("kind", "alpha-beta") != "alpha-beta":
        raise InputError(f"kinematics.kind must be 'alpha-beta' for instrument {name!r}, got {_short(spec['kind'])}",
                         value=spec.get("kind"), where=where)
    steps = (spec.get("alpha_steps", DEFAULT_STEPS[0]), spec.get("beta_steps", DEFAULT_STEPS[1]))
    alpha_range = spec.get("alpha_range", list(geom.alpha_range_deg))
    beta_range = spec.get("beta_range", [0.0, 180.0])
    seg = geom.beta_segment
    nominal = AlphaBeta(float(np.median(geom.alpha_arm)), float(np.hypot(*geom.fibres[fibre][0])), steps[0], steps[1],
                        beta_range, alpha_range=alpha_range)
    robots = []
    for p in range(len(geom.hole_ids)):
        f = geom.frames[p]
        turn = math.degrees(math.atan2(f[1, 0], f[0, 0]))
        if abs(np.linalg.det(f) - 1.0) > 1e-9:
            raise FormatError(f"instrument {name!r}: robot {geom.hole_ids[p]}'s hole frame is not a rotation",
                              value=geom.hole_ids[p], where=where)
        robots.append(AlphaBeta(float(geom.alpha_arm[p]), float(np.hypot(*geom.fibres[fibre][p])), steps[0], steps[1],
                                beta_range, alpha_range=alpha_range, segment=seg[p], fibre_point=geom.fibres[fibre][p],
                                offsets=(float(geom.alpha_offset_deg[p]) + turn, float(geom.beta_offset_deg[p]))))
    c0, c1 = _fiducial_rule()
    rules = {int(p): (c0, c1) for p in np.nonzero(geom.fiducial_watch)[0]} if geom.fiducial_watch is not None else {}
    out_layout = {"kind": "instrument", "name": name}
    if "fibre" in layout:
        out_layout["fibre"] = fibre
    return InstrumentSetup(out_layout, nominal, robots, np.array(geom.bases, float), float(geom.robot_buffer),
                           np.array(geom.obstacles, float), np.array(geom.obstacle_buffers, float), rules,
                           collision_definition(name))


def _fiducial_rule() -> tuple[float, float]:
    """kaiju's rule for robots beside a fiducial: ``β < c0 + c1·α`` is a collision."""
    from ..instruments.sdss_v import FIDUCIAL_WATCH

    return float(FIDUCIAL_WATCH[0]), float(FIDUCIAL_WATCH[1])


#: where a PROBLEM.json may name its fibre (one meaning wherever it is: the fibre ``xy_mm`` places)
FIBRE_PLACES = ("fibre", "layout.fibre", "start.fibre", "target.fibre")


def problem_fibre(data: dict, where: str | None) -> str | None:
    """The fibre a problem names (``docs/formats.md``): ``"fibre"`` at the top level, in ``layout``,
    or in the ``start``/``target`` object; each place must agree, and only an instrument layout
    has named fibres.  ``None`` when none is named (the instrument's default, BOSS)."""
    from ..instruments.sdss_v import FIBRES

    found = []
    for place in FIBRE_PLACES:
        obj = data if "." not in place else data.get(place.split(".")[0])
        if isinstance(obj, dict) and "fibre" in obj:
            found.append((place, obj["fibre"]))
    for place, value in found:
        if not isinstance(value, str) or value not in FIBRES:
            raise InputError(f"{place} must be one of {', '.join(FIBRES)}, got {_short(value)}", value=_short(value),
                             where=where)
    if len({value for _, value in found}) > 1:
        (p0, v0), (p1, v1) = found[0], next(f for f in found if f[1] != found[0][1])
        raise InputError(f"{p0} is {v0!r} but {p1} is {v1!r}: a problem places one fibre", value=[v0, v1], where=where)
    layout = data.get("layout")
    if found and not (isinstance(layout, dict) and layout.get("kind") == "instrument"):
        kind = layout.get("kind") if isinstance(layout, dict) else "missing"
        raise InputError(f"{found[0][0]}: only an instrument layout has named fibres (its robots carry several); "
                         f"a {_short(kind)} layout's fibre is the arm's end", value=found[0][1], where=where)
    return found[0][1] if found else None


def instrument_collision(setup: InstrumentSetup, collision: dict[str, Any]) -> dict[str, Any]:
    """PROBLEM.json's ``collision`` on an instrument layout: the instrument's own definition
    (``setup.collision``) where the file is silent; a ``margin`` given alone applies to the
    obstacles too (docs/formats.md)."""
    own = setup.collision
    out = dict({"buffer": own.buffer_mm, "margin": own.margin_mm}, **collision)
    if "margin" not in collision:
        out.setdefault("obstacle_margin", own.obstacle_margin_mm)
    return out


def definition_kept(setup: InstrumentSetup, buffers: np.ndarray, margin: float,
                    obstacle_margin: float) -> CollisionDefinition | None:
    """The instrument's collision definition when a problem's numbers (mm) are exactly it, else None."""
    own = setup.collision
    same = (np.all(buffers == own.buffer_mm) and margin == own.margin_mm and obstacle_margin == own.obstacle_margin_mm)
    return own if same else None
