"""Wok problems made easy: the folded configuration, kaiju-like random targets, targets by positioner ID.

A PROBLEM.json on a real wok lists one start and one target per robot, in the calibration
table's row order (``docs/instruments.md``).  These helpers write those lists:

- :func:`folded_configuration`: every robot at the folded lattice (SDSS-V: α 10°, β 170°);
- :func:`random_wok_targets`: kaiju's random targets, seeded: each robot a fibre position
  drawn uniformly over its reach, then the robots that collide drawn again until none does;
- :func:`wok_targets`: targets given by positioner ID (the instrument table's ``positionerID``),
  as fibre positions in wok mm (the fibre named) or as joint angles, the other robots folded;
- :func:`wok_problem`: a PROBLEM.json object from a start and a target.

Collisions are the instrument's own definition (:func:`.acceptance.collision_definition`,
the default of a problem on the wok): two robots collide when their beta segments are closer
than the sum of their buffers plus kaiju's step margin (2.0 + 2.0 + 0.0782 mm), a robot and a
fiducial or guide camera when closer than 2.0 + 3.0 mm, and a robot under kaiju's fiducial
rule when ``β < 41.2853 − 1.3085·α``.  Angles are kaiju's
commanded angles in degrees, within the problem's joint ranges (α in [0°, 360°), β in
[0°, 180°]), so :func:`supcoord.parse_problem` accepts what these return.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import InputError
from ..geometry.segments import segment_distance
from .acceptance import collision_definition
from .sdss_v import FIBRES, FIDUCIAL_WATCH, InstrumentGeometry, fibre_joints, load_instrument, robot_forward

__all__ = ["folded_configuration", "random_wok_targets", "wok_targets", "wok_problem", "TARGET_BETA_RANGE"]

#: the beta range of an instrument problem's joints (degrees; ``problems/instrument.py``)
TARGET_BETA_RANGE = (0.0, 180.0)
#: a configuration closer than this (mm) to touching counts as colliding here, so rounding
#: never turns a target these helpers accept into one the problem reader refuses
_SAFETY_MM = 1e-6


def _geometry(instrument: str | InstrumentGeometry) -> InstrumentGeometry:
    return instrument if isinstance(instrument, InstrumentGeometry) else load_instrument(instrument)


def folded_configuration(instrument: str | InstrumentGeometry = "sdss-v-apo") -> np.ndarray:
    """Every robot at the instrument's folded lattice: ``(N, 2)`` joint angles ``(α, β)`` in degrees.

    Parameters
    ----------
    instrument : str or InstrumentGeometry
        ``"sdss-v-apo"``, ``"sdss-v-lco"`` or a loaded geometry.

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` float array, degrees, rows in the calibration table's order.

    Raises
    ------
    InputError
        An unknown instrument.

    Examples
    --------
    >>> folded_configuration("sdss-v-apo")[:2].tolist()
    [[10.0, 170.0], [10.0, 170.0]]

    References
    ----------
    The folded lattice: C. Sayres et al., AJ 161, 92 (2021), and kaiju, as ``docs/instruments.md`` cites it; ``docs/references.md``.
    """
    geom = _geometry(instrument)
    return np.tile(np.asarray(geom.folded_deg, float), (len(geom.hole_ids), 1))


def _neighbours(geom: InstrumentGeometry) -> np.ndarray:
    """Robot pairs ``(a, b)``, ``a < b``, whose beta segments can come within their buffers."""
    reach = geom.alpha_arm + float(np.abs(geom.beta_segment[..., 0]).max())
    d = np.linalg.norm(geom.bases[:, None] - geom.bases[None], axis=-1)
    a, b = np.nonzero(np.triu(d < reach[:, None] + reach[None] + 2 * geom.robot_buffer + 1.0, 1))
    return np.stack([a, b], 1)


def _collided(geom: InstrumentGeometry, angles: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """Per robot: does it collide (module docstring) at ``angles`` ``(N, 2)`` degrees?"""
    n = len(geom.hole_ids)
    seg = robot_forward(geom, np.arange(n), angles[:, 0], angles[:, 1])
    hit = np.zeros(n, dtype=bool)
    a, b = pairs[:, 0], pairs[:, 1]
    d = segment_distance(seg[a, 0], seg[a, 1], seg[b, 0], seg[b, 1])
    rule = collision_definition(geom.name)
    close = d < 2 * rule.buffer_mm + rule.margin_mm + _SAFETY_MM
    hit[a[close]] = hit[b[close]] = True
    obs = geom.obstacles
    d_obs = segment_distance(seg[:, None, 0], seg[:, None, 1], obs[None, :, 0], obs[None, :, 1])
    hit |= np.any(d_obs < rule.buffer_mm + geom.obstacle_buffers[None] + rule.obstacle_margin_mm + _SAFETY_MM, axis=1)
    if geom.fiducial_watch is not None:
        c0, c1 = FIDUCIAL_WATCH
        hit |= geom.fiducial_watch & (angles[:, 1] < c0 + c1 * angles[:, 0] + 1e-9)
    return hit


def _draw(geom: InstrumentGeometry, robots: np.ndarray, fibre: str, rng: np.random.Generator) -> np.ndarray:
    """Random reachable targets for ``robots``: a fibre position uniform over the robot's reach
    (an annulus around its alpha axis), turned into right-handed angles; drawn again until the
    angles are inside the joint ranges.  ``(len(robots), 2)`` degrees."""
    out = np.empty((len(robots), 2))
    todo = np.arange(len(robots))
    lo_b, hi_b = TARGET_BETA_RANGE
    for _ in range(10_000):
        if not len(todo):
            return out
        p = robots[todo]
        la = geom.alpha_arm[p]
        rf = np.hypot(*geom.fibres[fibre][p].T)
        r_in, r_out = np.abs(rf - la) + 1e-9, rf + la - 1e-9
        r = np.sqrt(rng.uniform(r_in ** 2, r_out ** 2))
        t = rng.uniform(0.0, 2 * np.pi, len(p))
        xy = geom.bases[p] + np.stack([r * np.cos(t), r * np.sin(t)], 1)
        ab = fibre_joints(geom, p, xy, fibre)
        ok = np.all(np.isfinite(ab), axis=1) & (ab[:, 1] >= lo_b) & (ab[:, 1] <= hi_b)
        out[todo[ok]] = ab[ok]
        todo = todo[~ok]
    raise InputError(f"no target of robot {int(robots[todo[0]])} inside the joint ranges in 10,000 draws",
                     value=int(robots[todo[0]]))


def random_wok_targets(instrument: str | InstrumentGeometry = "sdss-v-apo", seed: int = 0, *,
                       fibre: str = "metrology", max_rounds: int = 1000) -> np.ndarray:
    """kaiju's random decollided targets on a wok, seeded: ``(N, 2)`` joint angles in degrees.

    As kaiju's ``getRandomPathPair`` makes them (``setXYUniform`` for every robot, then
    ``decollideGrid``): each robot's ``fibre`` goes to a point drawn uniformly over the annulus
    it can reach (radii ``|r_f − L|`` to ``r_f + L`` mm around its alpha axis, with ``L`` its alpha
    arm and ``r_f`` the fibre's distance from the beta axis), solved right-handed into angles;
    then, while any robot collides (module docstring), every colliding robot is drawn again.
    The random numbers are numpy's (``numpy.random.default_rng(seed)``), not kaiju's C
    ``rand()``: the same seed gives the same targets here, not kaiju's.

    Parameters
    ----------
    instrument : str or InstrumentGeometry
        ``"sdss-v-apo"``, ``"sdss-v-lco"`` or a loaded geometry.
    seed : int
        Seed of the random generator (an integer >= 0).
    fibre : str
        The fibre placed uniformly: ``"metrology"`` (kaiju's choice), ``"apogee"`` or ``"boss"``.
    max_rounds : int
        Rounds of drawing the colliding robots again before giving up (kaiju: 1000).

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` float array of ``(α, β)`` in degrees, α in [0, 360), β in [0, 180], rows in
        the calibration table's order; no two robots collide, none touches an obstacle.

    Raises
    ------
    InputError
        An unknown instrument or fibre, a bad seed, or ``max_rounds`` rounds without a
        collision-free configuration.

    Examples
    --------
    >>> ab = random_wok_targets("sdss-v-apo", seed=1)
    >>> ab.shape, bool(np.all((ab[:, 1] >= 0) & (ab[:, 1] <= 180)))
    ((500, 2), True)
    >>> bool(np.array_equal(ab, random_wok_targets("sdss-v-apo", seed=1)))
    True

    References
    ----------
    kaiju (``sdss/kaiju``) ``getRandomPathPair``, ``decollideGrid``, as ``docs/instruments.md`` cites it; ``docs/references.md``.
    """
    geom = _geometry(instrument)
    if fibre not in FIBRES:
        raise InputError(f"fibre must be one of {', '.join(FIBRES)}, got {fibre!r:.40}", value=fibre)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2 ** 63:
        raise InputError(f"seed must be an integer in [0, 2**63), got {seed!r:.40}", value=seed)
    if isinstance(max_rounds, bool) or not isinstance(max_rounds, (int, np.integer)) or not 1 <= max_rounds <= 10 ** 6:
        raise InputError(f"max_rounds must be an integer in [1, 1000000], got {max_rounds!r:.40}", value=max_rounds)
    rng = np.random.default_rng(int(seed))
    n = len(geom.hole_ids)
    pairs = _neighbours(geom)
    angles = _draw(geom, np.arange(n), fibre, rng)
    for _ in range(int(max_rounds)):
        hit = np.flatnonzero(_collided(geom, angles, pairs))
        if not len(hit):
            return angles
        angles[hit] = _draw(geom, hit, fibre, rng)
    raise InputError(f"no collision-free targets after {max_rounds} rounds ({len(hit)} robots still collide)",
                     value=int(len(hit)))


def wok_targets(instrument: str | InstrumentGeometry, targets: Mapping[Any, Any], *, form: str = "xy_mm",
                fibre: str = "boss", others: Any = None) -> np.ndarray:
    """Targets by positioner ID: ``(N, 2)`` joint angles in degrees, rows in the table's order.

    Parameters
    ----------
    instrument : str or InstrumentGeometry
        ``"sdss-v-apo"``, ``"sdss-v-lco"`` or a loaded geometry.
    targets : mapping
        Positioner ID (the ``positionerID`` of the instrument's table, as ``geom.positioner_ids``
        lists them; an int or a string of digits) -> ``[x, y]`` in wok mm (``form="xy_mm"``: where
        the named ``fibre`` goes, solved right-handed as kaiju does) or ``[α, β]`` in degrees
        (``form="alpha_beta_deg"``, kaiju's commanded angles).
    form : str
        ``"xy_mm"`` or ``"alpha_beta_deg"``.
    fibre : str
        With ``"xy_mm"``: ``"boss"`` (the default, every robot has one), ``"apogee"`` (robots in
        an ``ApogeeBoss`` hole) or ``"metrology"``.
    others : array-like, optional
        ``(N, 2)`` degrees for the robots not in ``targets``; default
        :func:`folded_configuration`.

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` float array of ``(α, β)`` in degrees.

    Raises
    ------
    InputError
        An unknown positioner ID, a position out of the robot's reach or outside the joint
        ranges, a robot without the fibre named; the message names the ID and the value.

    Examples
    --------
    >>> from supcoord.instruments import fibre_xy
    >>> g = load_instrument("sdss-v-apo")
    >>> pid = g.positioner_ids[7]
    >>> xy = fibre_xy(g, 7, 40.0, 100.0, "boss")          # where robot 7's BOSS fibre is at (40°, 100°)
    >>> ab = wok_targets(g, {pid: xy.tolist()}, fibre="boss")
    >>> np.round(ab[7], 6).tolist(), ab[0].tolist()
    ([40.0, 100.0], [10.0, 170.0])

    References
    ----------
    kaiju (``sdss/kaiju``) ``Robot::alphaBetaFromWokXYZ``, as ``docs/instruments.md`` cites it; ``docs/references.md``.
    """
    geom = _geometry(instrument)
    if form not in ("xy_mm", "alpha_beta_deg"):
        raise InputError(f"form must be 'xy_mm' or 'alpha_beta_deg', got {form!r:.40}", value=form)
    if fibre not in FIBRES:
        raise InputError(f"fibre must be one of {', '.join(FIBRES)}, got {fibre!r:.40}", value=fibre)
    n = len(geom.hole_ids)
    out = folded_configuration(geom) if others is None else _angles(others)
    if out is None or out.shape != (n, 2) or not np.all(np.isfinite(out)):
        raise InputError(f"others must be {n} finite (alpha, beta) pairs in degrees", value=None)
    row = {pid: i for i, pid in enumerate(geom.positioner_ids)}
    for key, value in targets.items():
        pid = int(key) if isinstance(key, str) and key.isascii() and key.isdigit() else key
        if isinstance(pid, bool) or not isinstance(pid, (int, np.integer)) or int(pid) not in row:
            raise InputError(f"targets: {key!r:.40} is not a positioner ID of {geom.name}", value=key)
        p = row[int(pid)]
        v = np.asarray(value, dtype=float) if _pair(value) else None
        if v is None:
            raise InputError(f"targets[{key}] must be a pair of finite numbers, got {value!r:.60}", value=value)
        if form == "xy_mm":
            if fibre == "apogee" and geom.has_apogee is not None and not geom.has_apogee[p]:
                raise InputError(f"targets[{key}]: positioner {key} has no APOGEE fibre (a Boss hole)", value=key)
            a, b = fibre_joints(geom, p, v, fibre)
            if not np.isfinite(a):
                rf = float(np.hypot(*geom.fibres[fibre][p]))
                la = float(geom.alpha_arm[p])
                raise InputError(f"targets[{key}]: {fibre} fibre position {v.tolist()} is "
                                 f"{float(np.hypot(*(v - geom.bases[p]))):.3f} mm from the robot's alpha axis, outside "
                                 f"its reach [{abs(rf - la):.3f}, {rf + la:.3f}] mm", value=v.tolist())
        else:
            a, b = float(v[0]) % 360.0, float(v[1])
        if not TARGET_BETA_RANGE[0] <= b <= TARGET_BETA_RANGE[1]:
            raise InputError(f"targets[{key}]: beta {b:.3f} deg is outside the beta range "
                             f"{list(TARGET_BETA_RANGE)}", value=[float(a), float(b)])
        out[p] = a, b
    return out


def _angles(value: Any) -> np.ndarray | None:
    """``value`` as a float array, or None when it is not numbers."""
    try:
        return np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return None


def _pair(value: Any) -> bool:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return False
    return v.shape == (2,) and bool(np.all(np.isfinite(v)))


def wok_problem(instrument: str | InstrumentGeometry, start: Any, target: Any, *, name: str | None = None,
                description: str | None = None) -> dict:
    """A PROBLEM.json object on a real wok from a start and a target in joint angles.

    Parameters
    ----------
    instrument : str or InstrumentGeometry
        ``"sdss-v-apo"``, ``"sdss-v-lco"`` or a loaded geometry.
    start, target : array-like
        ``(N, 2)`` joint angles ``(α, β)`` in degrees, rows in the calibration table's order
        (:func:`folded_configuration`, :func:`random_wok_targets`, :func:`wok_targets`).
    name, description : str, optional
        Kept in the file as its ``name`` and ``description``.

    Returns
    -------
    dict
        ``{"layout": {"kind": "instrument", ...}, "start": {"alpha_beta_deg": ...}, "target":
        {...}}``: give it to :func:`supcoord.parse_problem`, or write it with :func:`json.dump`.

    Raises
    ------
    InputError
        An unknown instrument, or a start or target that is not ``(N, 2)`` finite angles.

    Examples
    --------
    >>> d = wok_problem("sdss-v-apo", folded_configuration(), random_wok_targets(seed=2))
    >>> d["layout"], len(d["target"]["alpha_beta_deg"])
    ({'kind': 'instrument', 'name': 'sdss-v-apo'}, 500)

    References
    ----------
    The PROBLEM.json format with instrument layouts: ``docs/formats.md``, ``docs/instruments.md``.
    """
    geom = _geometry(instrument)
    n = len(geom.hole_ids)
    conf = {}
    for what, value in (("start", start), ("target", target)):
        a = _angles(value)
        if a is None or a.shape != (n, 2) or not np.all(np.isfinite(a)):
            got = f"shape {a.shape}" if a is not None else f"{value!r:.40}"
            raise InputError(f"{what} must be {n} finite (alpha, beta) pairs in degrees, got {got}", value=got)
        conf[what] = {"alpha_beta_deg": [[float(x), float(y)] for x, y in a]}
    out: dict[str, Any] = {}
    if name is not None:
        out["name"] = str(name)
    if description is not None:
        out["description"] = str(description)
    out.update({"layout": {"kind": "instrument", "name": geom.name}, **conf})
    return out
