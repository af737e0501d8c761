"""SDSS-V's two focal planes (APO, LCO) from their measured calibrations, modelled as kaiju does.

The tables are SDSS-V's FPS calibrations (``sdss/fps_calibrations``, release 2025.12.04),
shipped unchanged in ``data/sdss_v``; every number that is not in them (collision segment,
buffers, obstacles, ranges, folded lattice) is SDSS-V's planner kaiju's, with its file and
line in :attr:`InstrumentGeometry.sources` and ``docs/instruments.md``.

Forward kinematics (kaiju ``Robot::setAlphaBeta`` with coordio's ``positionerToTangent`` and
``tangentToWok``), for robot ``p`` at joint angles ``(α, β)`` in degrees and a point ``P`` of
the beta-arm frame (origin on the beta axis, +x along the arm)::

    tangent(P) = L·u(α + α₀) + R(α + α₀ + β + β₀)·P        u(θ) = (cos θ, sin θ)
    focal(P)   = hole + F·(tangent(P) + (dx, dy)) = bases[p] + F·tangent(P)

with ``L`` the measured alpha arm, ``α₀, β₀`` the table's ``alphaOffset, betaOffset``, ``F``
the hole's tangent-to-wok rotation (columns: the x, y parts of its ``i``, ``j`` vectors; every
hole of both woks has ``i = (0, −1, 0)``, ``j = (1, 0, 0)``, a −90° turn) and ``dx, dy`` the
table's offsets, which kaiju adds in the tangent frame, i.e. rotated by ``F``.

>>> geom = load_instrument("sdss-v-apo")
>>> len(geom.hole_ids), geom.obstacle_kinds.count("fiducial"), geom.obstacle_kinds.count("gfa")
(500, 60, 6)
>>> geom.beta_segment[0].round(4).tolist(), geom.robot_buffer, geom.folded_deg
([[0.0, 0.0], [14.7276, 0.0]], 2.0, (10.0, 170.0))
>>> robot_forward(geom, 0, 30.0, 120.0).shape, fibre_xy(geom, 0, [0, 90], [180, 180]).shape
((2, 2), (2, 2))
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..errors import FormatError, InputError
from ._tables import parse_table, read_text

__all__ = ["InstrumentGeometry", "INSTRUMENTS", "load_instrument", "robot_forward", "fibre_xy", "fibre_joints",
           "robot_collision_distance"]

INSTRUMENTS: tuple[str, ...] = ("sdss-v-apo", "sdss-v-lco")
_SITES = {"sdss-v-apo": ("apo", "APO"), "sdss-v-lco": ("lco", "LCO")}
FIBRES = ("metrology", "apogee", "boss")

#: sdss/kaiju 1.4.1 (tag ``1.4.1``); the cited files are unchanged at the newer 065b48f
KAIJU_COMMIT = "853b765257d51419bcc43f112726c336ea7d4899"
#: sdss/coordio (kaiju 1.4.1's sdist ships this ``cextern/conv.cpp`` unchanged)
COORDIO_COMMIT = "899b78e2d45b52f940bb9f5abd55c20a6d75db14"
#: sdss/jaeger, SDSS-V's robot controller (the operational folded lattice)
JAEGER_COMMIT = "7d08f3822cd39ff7d7844ea5ace33f528004fae8"
CALIBRATIONS = "SDSS-V FPS calibrations (sdss/fps_calibrations), release 2025.12.04, " \
               "commit e7867464fe410188e8aa93cbcbd4eb113afed005"


def _k(path: str, line: str) -> str:
    return f"kaiju {path}:{line} @{KAIJU_COMMIT}"


def _c(path: str, line: str) -> str:
    return f"coordio {path}:{line} @{COORDIO_COMMIT}"


# ---- kaiju's numbers (each with its source) -------------------------------------------
BETA_LEN = 16.2              # coordio defaults.py: beta axis to the flat top of the beta arm
TIP_FLAT = 0.6               # kaiju: length of the beta arm's flat top
CORNER_PROTECTION = 0.55     # kaiju
ROBOT_BUFFER = 2.0           # kaiju _load_from_tables: collisionBuffer=2
FIDUCIAL_BUFFER = 3.0        # kaiju _load_from_tables: addFiducial(..., collisionBuffer=3)
GFA_BUFFER = 3.0             # kaiju _load_from_tables: addGFA(..., collisionBuffer=3)
ELEMENT_HEIGHT = 143.1       # coordio POSITIONER_HEIGHT: wok surface to fibre (z of every segment)
#: kaiju's GFA collision segments (x0, y0, x1, y1) mm, hard-coded, the same at both sites;
#: kaiju's GFA ``i`` is the calibration table's GFA ``id`` i + 1 (same direction)
GFA_SEGMENTS = (
    (-267.49, 89.15, -210.95, 187.08),
    (-56.54, 276.23, 56.54, 276.23),
    (210.95, 187.07, 267.49, 89.15),
    (267.49, -89.15, 210.95, -187.08),
    (56.54, -276.23, -56.54, -276.23),
    (-210.95, -187.07, -267.49, -89.15),
)
ALPHA_RANGE = (0.0, 360.0)   # kaiju handleLimits clamps alpha to [0, 360]
BETA_RANGE = (0.0, 360.0)    # ... and beta to [0, 360] as well (targets: right-handed, beta <= 180)
FOLDED = (10.0, 170.0)       # jaeger kaiju.lattice_position (and kaiju's own examples)
#: kaiju's rough arm lengths in its step-displacement margin (robotGrid.cpp)
ROUGH_ARMS = (7.4, 15.0)
#: kaiju's "fiducial watch" rule: beta < C0 + C1·alpha counts as collided for flagged robots
FIDUCIAL_WATCH = (41.2853, -1.3085)

_SOURCES = {
    "beta_segment": _k("python/kaiju/robotGrid.py", "410-426") + " (tipFlat 0.6 :414, cornerProtection 0.55 "
                    ":419, end = BETA_LEN - (sqrt(buffer^2 + (tipFlat/2)^2) - cornerProtection) :420-425); "
                    + _c("src/coordio/defaults.py", "37") + " (BETA_LEN 16.2)",
    "robot_buffer": _k("python/kaiju/robotGrid.py", "1112") + " (collisionBuffer=2; default 2 at :407)",
    "fiducial_buffer": _k("python/kaiju/robotGrid.py", "1119") + " (addFiducial collisionBuffer=3)",
    "gfa_buffer": _k("python/kaiju/robotGrid.py", "1152") + " (addGFA collisionBuffer=3)",
    "gfa_segments": _k("python/kaiju/robotGrid.py", "1124-1149") + " (hard-coded, both sites)",
    "fiducials": "fps_calibrations {site}_fiducialCoords.csv:id,xWok,yWok (zWok 143.1)",
    "bases": "fps_calibrations {site}_wokCoords.csv:xWok,yWok,ix,iy,jx,jy + {site}_positionerTable.csv:dx,dy; "
             + _k("python/kaiju/robotGrid.py", "1098-1103") + "; " + _c("cextern/conv.cpp", "132-153"),
    "alpha_arm": "fps_calibrations {site}_positionerTable.csv:alphaArmLen; "
                 + _k("python/kaiju/robotGrid.py", "1104"),
    "fibres": "fps_calibrations {site}_positionerTable.csv:metX,metY,apX,apY,bossX,bossY; "
              + _k("python/kaiju/robotGrid.py", "1108-1110"),
    "offsets": "fps_calibrations {site}_positionerTable.csv:alphaOffset,betaOffset; "
               + _k("python/kaiju/robotGrid.py", "1105-1106") + "; " + _c("cextern/conv.cpp", "229-255"),
    "forward": _k("src/robot.cpp", "104-161") + "; " + _c("cextern/conv.cpp", "116-156,229-255"),
    "handedness": _k("python/kaiju/robotGrid.py", "407") + " (lefthanded=False, not overridden :1095-1113); "
                  + _c("cextern/conv.cpp", "294-302"),
    "alpha_range": _k("src/robotGrid.cpp", "1003-1022") + " (handleLimits)",
    "beta_range": _k("src/robotGrid.cpp", "1024-1037") + " (handleLimits: [0, 360], not 180)",
    "folded": f"jaeger src/jaeger/etc/jaeger_APO.yml:81, jaeger_LCO.yml:81 @{JAEGER_COMMIT} "
              "(lattice_position [10, 170]); " + _k("bin/runSim.py", "39-40"),
    "element_height": _c("src/coordio/defaults.py", "35") + " (POSITIONER_HEIGHT 143.1); "
                      + _k("python/kaiju/robotGrid.py", "1107"),
    "robot_collision_distance": _k("src/robotGrid.cpp", "813") + " (buffer1 + buffer2 + maxDisplacement; "
                                "maxDisplacement = 2 sin(angStep)(7.4 + 15) :32, :13-14)",
    "obstacle_collision_distance": _k("src/robotGrid.cpp", "839,874") + " (robot buffer + obstacle buffer)",
    "target_fibre": _k("src/robot.cpp", "530-560") + " (a target's fiberType picks met/apogee/boss)",
    "fiducial_watch": _k("python/kaiju/robotGrid.py", "1159-1180") + "; " + _k("src/robotGrid.cpp", "22-23,851-855"),
}


@dataclass(frozen=True, eq=False)
class InstrumentGeometry:
    """One SDSS-V focal plane: robots in the positioner table's row order, obstacles, kaiju's numbers.

    Arrays are read-only. ``sources`` maps each number's name to where it comes from. The
    fields after ``sources`` are extras kaiju also uses: ``hole_xy`` (kaiju's ``basePos``,
    offsets not applied), ``frames`` (``F`` of the module docstring, ``(N, 2, 2)``),
    ``has_apogee`` (``"Apogee"`` in the hole type) and ``fiducial_watch`` (robots kaiju forbids
    ``β < 41.2853 − 1.3085·α``, near a fiducial).
    """

    name: str
    hole_ids: tuple[str, ...]
    positioner_ids: tuple[int, ...]
    bases: np.ndarray
    alpha_arm: np.ndarray
    beta_segment: np.ndarray
    fibres: dict[str, np.ndarray]
    alpha_offset_deg: np.ndarray
    beta_offset_deg: np.ndarray
    robot_buffer: float
    obstacles: np.ndarray
    obstacle_buffers: np.ndarray
    obstacle_kinds: tuple[str, ...]
    obstacle_ids: tuple[str, ...]
    folded_deg: tuple[float, float]
    alpha_range_deg: tuple[float, float]
    beta_range_deg: tuple[float, float]
    sources: dict[str, str]
    hole_xy: np.ndarray | None = None
    frames: np.ndarray | None = None
    has_apogee: np.ndarray | None = None
    fiducial_watch: np.ndarray | None = None

    def __repr__(self) -> str:
        return (f"InstrumentGeometry({self.name!r}: {len(self.hole_ids)} robots, {len(self.obstacle_ids)} "
                f"obstacles)")


def _frozen(a) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def _frozen_bool(a) -> np.ndarray:
    a = np.array(a, dtype=bool)
    a.setflags(write=False)
    return a


def _check_flat(file: str, what: str, values: np.ndarray, expected: float) -> None:
    bad = np.flatnonzero(np.abs(values - expected) > 1e-9)
    if bad.size:
        raise FormatError(f"{what} must be {expected:g} (a flat wok, as this model assumes); row {bad[0] + 1} "
                          f"has {values[bad[0]]:g}", value=float(values[bad[0]]), where=file)


@lru_cache(maxsize=4)
def _load(name: str, data_dir: str | None) -> dict:
    """The fields of :class:`InstrumentGeometry` from the site's calibration tables, checked
    (a flat wok, orthonormal hole frames, distinct fiducial IDs), arrays read-only."""
    site, site_name = _SITES[name]
    fp, fw, ff = (f"{site}_positionerTable.csv", f"{site}_wokCoords.csv", f"{site}_fiducialCoords.csv")
    pos, wok, fid = _read_tables(site, site_name, data_dir)
    rows = _robot_rows(pos, wok, fp, fw)
    ids = pos["positionerID"]
    w = np.asarray(rows)
    for col, expected in (("zWok", 0.0), ("iz", 0.0), ("jz", 0.0), ("kx", 0.0), ("ky", 0.0), ("kz", 1.0)):
        _check_flat(f"{fw}: {col}", col, wok[col][w], expected)
    _check_flat(f"{ff}: zWok", "zWok", fid["zWok"], ELEMENT_HEIGHT)
    frames = np.stack([np.stack([wok["ix"][w], wok["jx"][w]], -1), np.stack([wok["iy"][w], wok["jy"][w]], -1)], -2)
    if not np.allclose(frames @ np.swapaxes(frames, -1, -2), np.eye(2), atol=1e-6) or \
            not np.allclose(np.linalg.det(frames), 1.0, atol=1e-6):
        raise FormatError("hole i, j vectors must be orthonormal and right-handed", value=None, where=f"{fw}: ix")
    hole_xy = np.stack([wok["xWok"][w], wok["yWok"][w]], -1)
    dxy = np.stack([pos["dx"], pos["dy"]], -1)
    bases = hole_xy + np.einsum("nij,nj->ni", frames, dxy)
    n = len(rows)
    beta_end = BETA_LEN - (math.hypot(ROBOT_BUFFER, TIP_FLAT / 2) - CORNER_PROTECTION)
    seg = np.broadcast_to(np.array([[0.0, 0.0], [beta_end, 0.0]]), (n, 2, 2))
    fibres = {f: _frozen(np.stack([pos[x], pos[y]], -1)) for f, (x, y) in
              zip(FIBRES, (("metX", "metY"), ("apX", "apY"), ("bossX", "bossY")))}
    fxy = np.stack([fid["xWok"], fid["yWok"]], -1)
    obstacles = np.concatenate([np.stack([fxy, fxy], 1), np.array(GFA_SEGMENTS).reshape(-1, 2, 2)])
    kinds = ("fiducial",) * len(fxy) + ("gfa",) * len(GFA_SEGMENTS)
    obstacle_ids = tuple(fid["id"]) + tuple(f"GFA{i + 1}" for i in range(len(GFA_SEGMENTS)))
    if len(set(obstacle_ids)) != len(obstacle_ids):
        raise FormatError("duplicate fiducial id", value=None, where=f"{ff}: id")
    watch = _watched_holes(fid)
    return {
        "hole_ids": tuple(pos["holeID"]), "positioner_ids": tuple(int(i) for i in ids), "bases": _frozen(bases),
        "alpha_arm": _frozen(pos["alphaArmLen"]), "beta_segment": _frozen(seg), "fibres": fibres,
        "alpha_offset_deg": _frozen(pos["alphaOffset"]), "beta_offset_deg": _frozen(pos["betaOffset"]),
        "obstacles": _frozen(obstacles),
        "obstacle_buffers": _frozen([FIDUCIAL_BUFFER] * len(fxy) + [GFA_BUFFER] * len(GFA_SEGMENTS)),
        "obstacle_kinds": kinds, "obstacle_ids": obstacle_ids, "hole_xy": _frozen(hole_xy),
        "frames": _frozen(frames), "has_apogee": _frozen_bool(["Apogee" in wok["holeType"][i] for i in rows]),
        "fiducial_watch": _frozen_bool([h in watch for h in pos["holeID"]]),
        "sources": {k: v.replace("{site}", site) for k, v in _SOURCES.items()},
    }


def _read_tables(site: str, site_name: str, data_dir: str | None) -> tuple[dict, dict, dict]:
    """The site's positioner, wok and fiducial tables (the GFA table is read and checked too;
    kaiju models the GFAs by its own segments), every row of the site ``site_name``."""
    fp, fw, ff = (f"{site}_positionerTable.csv", f"{site}_wokCoords.csv", f"{site}_fiducialCoords.csv")
    pos = parse_table(fp, read_text(fp, data_dir), texts=("site", "holeID"), numbers=(
        "positionerID", "alphaArmLen", "metX", "metY", "apX", "apY", "bossX", "bossY",
        "alphaOffset", "betaOffset", "dx", "dy"))
    wok = parse_table(fw, read_text(fw, data_dir), texts=("site", "holeID", "holeType"), numbers=(
        "xWok", "yWok", "zWok", "ix", "iy", "iz", "jx", "jy", "jz", "kx", "ky", "kz"))
    fid = parse_table(ff, read_text(ff, data_dir), texts=("site", "holeID", "id"),
                      numbers=("xWok", "yWok", "zWok"), optional_numbers=("row", "col"))
    fg = f"{site}_gfaCoords.csv"   # read for validation; kaiju models GFAs by its own segments
    gfa = parse_table(fg, read_text(fg, data_dir), texts=("site",), numbers=("id", "xWok", "yWok"))
    for file, table in ((fp, pos), (fw, wok), (ff, fid), (fg, gfa)):
        other = sorted(set(table["site"]) - {site_name})
        if other:
            raise FormatError(f"site must be {site_name}", value=other[0], where=f"{file}: site")
    return pos, wok, fid


def _robot_rows(pos: dict, wok: dict, fp: str, fw: str) -> list[int]:
    """Per robot of the positioner table, its hole's row in the wok table (one robot per robot
    hole, distinct integer positioner IDs)."""
    holes = {h: i for i, h in enumerate(wok["holeID"])}
    if len(holes) != len(wok["holeID"]):
        raise FormatError("duplicate holeID", value=next(h for h in holes if wok["holeID"].count(h) > 1),
                          where=f"{fw}: holeID")
    rows = []
    for k, h in enumerate(pos["holeID"]):
        if h not in holes or "Fiducial" in wok["holeType"][holes[h]]:
            raise FormatError(f"row {k + 1}: no robot hole {h!r} in {fw}", value=h, where=f"{fp}: holeID")
        rows.append(holes[h])
    if len(set(rows)) != len(rows):
        raise FormatError("two robots in one hole", value=len(rows) - len(set(rows)), where=f"{fp}: holeID")
    ids = pos["positionerID"]
    if np.any(ids != np.round(ids)) or len(set(ids.tolist())) != len(ids):
        raise FormatError("positionerID must be distinct integers", value=None, where=f"{fp}: positionerID")
    return rows


def _watched_holes(fid: dict) -> set[str]:
    """The holes beside a fiducial whose robots obey kaiju's joint rule, from the fiducials' row
    and column."""
    watch = set()
    for r, c in zip(fid["row"], fid["col"]):        # kaiju robotGrid.py:1159-1176, verbatim
        if math.isnan(r) or math.isnan(c):
            continue
        p_row = int(r + 1)
        p_col = int(c - 1) if p_row > 0 else int(c)
        watch.add(f"R{'+' if p_row > 0 else ''}{p_row}C{p_col}")
    return watch


def load_instrument(name: str, *, data_dir: str | Path | None = None) -> InstrumentGeometry:
    """The SDSS-V focal plane ``name`` from its calibration tables.

    The tables are parsed once per name and directory (cached); each call returns a new
    object sharing the read-only arrays.

    Parameters
    ----------
    name : str
        ``"sdss-v-apo"`` or ``"sdss-v-lco"`` (case-insensitive).
    data_dir : str or os.PathLike, optional
        A directory holding the same-named CSV files, read instead of the package data.

    Returns
    -------
    InstrumentGeometry
        Robots in the positioner table's order: bases, alpha arms and beta segments (mm),
        offsets (degrees), fibres; fiducials and guide cameras as obstacles with buffers (mm).

    Raises
    ------
    InputError
        An unknown name.
    FormatError
        A calibration table that is missing, malformed or inconsistent (named with its line).

    Examples
    --------
    >>> load_instrument("sdss-v-lco").positioner_ids[:2]
    (1157, 41)
    >>> load_instrument("desi")
    Traceback (most recent call last):
    ...
    supcoord.errors.InputError: unknown instrument 'desi' (known: sdss-v-apo, sdss-v-lco)

    References
    ----------
    C. Sayres et al., SDSS-V Algorithms: Fast, Collision-free Trajectory Planning for Heavily
    Overlapping Robotic Fiber Positioners, AJ 161, 92 (2021); kaiju (``sdss/kaiju``) and the
    SDSS-V FPS calibrations (``sdss/fps_calibrations``), ``docs/references.md``.
    """
    key = str(name).strip().lower()
    if key not in _SITES:
        raise InputError(f"unknown instrument {name!r} (known: {', '.join(INSTRUMENTS)})", value=name)
    d = _load(key, None if data_dir is None else str(Path(data_dir).resolve()))
    return InstrumentGeometry(
        name=key, robot_buffer=ROBOT_BUFFER, folded_deg=FOLDED, alpha_range_deg=ALPHA_RANGE,
        beta_range_deg=BETA_RANGE, **{**d, "fibres": dict(d["fibres"]), "sources": dict(d["sources"])})


def _frames(geom: InstrumentGeometry) -> np.ndarray:
    if geom.frames is not None:
        return geom.frames
    return np.broadcast_to(np.array([[0.0, 1.0], [-1.0, 0.0]]), (len(geom.hole_ids), 2, 2))


def _robot(geom: InstrumentGeometry, p) -> np.ndarray:
    """``p`` as an integer index array into ``geom.hole_ids`` (an :class:`InputError` otherwise)."""
    p = np.asarray(p)
    n = len(geom.hole_ids)
    if not np.issubdtype(p.dtype, np.integer) or (p.size and (p.min() < 0 or p.max() >= n)):
        raise InputError(f"robot index must be an integer in [0, {n}), got {p.tolist()!r:.60}", value=p.tolist())
    return p


def _to_focal(geom: InstrumentGeometry, p, alpha_deg, beta_deg, pts: np.ndarray) -> np.ndarray:
    """Beta-frame points ``pts`` (``(..., K, 2)`` broadcast with ``p, α, β``) in the focal plane."""
    a = np.radians(np.asarray(alpha_deg, float) + geom.alpha_offset_deg[p])
    ab = a + np.radians(np.asarray(beta_deg, float) + geom.beta_offset_deg[p])
    length = geom.alpha_arm[p]
    elbow = np.stack([length * np.cos(a), length * np.sin(a)], -1)[..., None, :]
    c, s = np.cos(ab)[..., None], np.sin(ab)[..., None]
    x, y = pts[..., 0], pts[..., 1]
    tangent = elbow + np.stack([c * x - s * y, s * x + c * y], -1)
    frames = _frames(geom)[p][..., None, :, :]
    return geom.bases[p][..., None, :] + np.einsum("...ij,...j->...i", frames, tangent)


def robot_forward(geom: InstrumentGeometry, p, alpha_deg, beta_deg) -> np.ndarray:
    """Robot ``p``'s beta collision segment in the focal plane at given joint angles.

    The angles are kaiju's commanded angles: the table's ``alphaOffset`` and ``betaOffset``
    are added here, and ``dx, dy`` are in ``geom.bases`` (kaiju ``Robot::setAlphaBeta``,
    ``collisionSegWokXYZ``). Counter-clockwise positive.

    Parameters
    ----------
    geom : InstrumentGeometry
        The focal plane (:func:`load_instrument`).
    p : int or array of int
        Robot indices into ``geom.hole_ids``; broadcast with the angles.
    alpha_deg, beta_deg : float or array
        Commanded joint angles (degrees).

    Returns
    -------
    numpy.ndarray
        ``(..., 2, 2)`` in mm: ``[..., 0, :]`` the segment's start (on the beta axis),
        ``[..., 1, :]`` its end.

    Raises
    ------
    InputError
        A robot index that is not an integer in ``[0, N)``.

    Examples
    --------
    >>> g = load_instrument("sdss-v-apo")
    >>> robot_forward(g, [0, 1], 10.0, 170.0).shape
    (2, 2, 2)

    References
    ----------
    C. Sayres et al., SDSS-V Algorithms: Fast, Collision-free Trajectory Planning for Heavily
    Overlapping Robotic Fiber Positioners, AJ 161, 92 (2021); kaiju (``sdss/kaiju``) and the
    SDSS-V FPS calibrations (``sdss/fps_calibrations``), ``docs/references.md``.
    """
    p = _robot(geom, p)
    return _to_focal(geom, p, alpha_deg, beta_deg, geom.beta_segment[p])


def fibre_xy(geom: InstrumentGeometry, p, alpha_deg, beta_deg, fibre: str = "boss") -> np.ndarray:
    """Robot ``p``'s fibre in the focal plane at given joint angles.

    Kaiju's ``metWokXYZ``/``apWokXYZ``/``bossWokXYZ`` (x, y) at the same angles as
    :func:`robot_forward`.

    Parameters
    ----------
    geom : InstrumentGeometry
        The focal plane (:func:`load_instrument`).
    p : int or array of int
        Robot indices into ``geom.hole_ids``; broadcast with the angles.
    alpha_deg, beta_deg : float or array
        Commanded joint angles (degrees).
    fibre : str, default "boss"
        ``"metrology"``, ``"apogee"`` or ``"boss"``.

    Returns
    -------
    numpy.ndarray
        ``(..., 2)`` focal-plane positions (mm).

    Raises
    ------
    InputError
        An unknown fibre or a bad robot index.

    Examples
    --------
    >>> g = load_instrument("sdss-v-apo")
    >>> xy = fibre_xy(g, 7, 40.0, 100.0)
    >>> xy.shape, bool(np.hypot(*(xy - g.bases[7])) < 7.6 + 15.0)
    ((2,), True)

    References
    ----------
    C. Sayres et al., SDSS-V Algorithms: Fast, Collision-free Trajectory Planning for Heavily
    Overlapping Robotic Fiber Positioners, AJ 161, 92 (2021); kaiju (``sdss/kaiju``) and the
    SDSS-V FPS calibrations (``sdss/fps_calibrations``), ``docs/references.md``.
    """
    if fibre not in FIBRES:
        raise InputError(f"unknown fibre {fibre!r} (known: {', '.join(FIBRES)})", value=fibre)
    p = _robot(geom, p)
    return _to_focal(geom, p, alpha_deg, beta_deg, geom.fibres[fibre][p][..., None, :])[..., 0, :]


def fibre_joints(geom: InstrumentGeometry, p, xy, fibre: str = "boss") -> np.ndarray:
    """Joint angles putting robot ``p``'s ``fibre`` on a focal-plane point (inverse of :func:`fibre_xy`).

    Kaiju's right-handed solution (``Robot::alphaBetaFromWokXYZ``, coordio
    ``tangentToPositioner``).

    Parameters
    ----------
    geom : InstrumentGeometry
        The focal plane (:func:`load_instrument`).
    p : int or array of int
        Robot indices into ``geom.hole_ids``; broadcast with ``xy``.
    xy : array, ``(..., 2)``
        Focal-plane points (mm).
    fibre : str, default "boss"
        ``"metrology"``, ``"apogee"`` or ``"boss"``.

    Returns
    -------
    numpy.ndarray
        ``(..., 2)`` commanded ``(alpha, beta)`` in degrees, alpha in ``[0, 360)``; NaN where
        ``xy`` is out of reach.

    Raises
    ------
    InputError
        An unknown fibre or a bad robot index.

    Examples
    --------
    >>> g = load_instrument("sdss-v-apo")
    >>> ab = fibre_joints(g, 7, fibre_xy(g, 7, 40.0, 100.0))
    >>> np.allclose(ab, [40.0, 100.0])
    True

    References
    ----------
    C. Sayres et al., SDSS-V Algorithms: Fast, Collision-free Trajectory Planning for Heavily
    Overlapping Robotic Fiber Positioners, AJ 161, 92 (2021); kaiju (``sdss/kaiju``), coordio (``sdss/coordio``) and the
    SDSS-V FPS calibrations (``sdss/fps_calibrations``), ``docs/references.md``.
    """
    if fibre not in FIBRES:
        raise InputError(f"unknown fibre {fibre!r} (known: {', '.join(FIBRES)})", value=fibre)
    p = _robot(geom, p)
    d = np.asarray(xy, float) - geom.bases[p]
    t = np.einsum("...ji,...j->...i", _frames(geom)[p], d)      # Fᵀ: focal -> tangent
    fb = geom.fibres[fibre][p]
    la, r_b = geom.alpha_arm[p], np.hypot(fb[..., 0], fb[..., 1])
    r_t2 = (t * t).sum(-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        gamma = np.degrees(np.arccos((la * la + r_b * r_b - r_t2) / (2 * la * r_b)))
        xi = np.degrees(np.arccos((la * la + r_t2 - r_b * r_b) / (2 * la * np.sqrt(r_t2))))
    theta_t = np.degrees(np.arctan2(t[..., 1], t[..., 0]))
    theta_b = np.degrees(np.arctan2(fb[..., 1], fb[..., 0]))
    alpha = np.mod(theta_t - xi - geom.alpha_offset_deg[p], 360.0)
    beta = 180.0 - gamma - theta_b - geom.beta_offset_deg[p]
    return np.stack([alpha, beta], -1)


def robot_collision_distance(geom: InstrumentGeometry, ang_step_deg: float = 0.0) -> float:
    """Kaiju's robot-robot collision distance between two beta segments.

    Two robots collide when their segments are closer than ``2·robot_buffer`` plus kaiju's
    step margin ``2·sin(ang_step)·(7.4 + 15)`` (``RobotGrid::robotColliders``). Obstacles
    use ``robot_buffer + obstacle_buffers`` with no margin.

    Parameters
    ----------
    geom : InstrumentGeometry
        The focal plane (:func:`load_instrument`).
    ang_step_deg : float, default 0.0
        kaiju's planning step (degrees, >= 0; kaiju's default is 0.1).

    Returns
    -------
    float
        The distance (mm): 4.0 at 0, 4.078 at 0.1°, 4.782 at 1°.

    Raises
    ------
    InputError
        A step that is negative or not finite.

    Examples
    --------
    >>> g = load_instrument("sdss-v-apo")
    >>> [round(robot_collision_distance(g, s), 4) for s in (0, 0.1, 1)]
    [4.0, 4.0782, 4.7819]

    References
    ----------
    C. Sayres et al., SDSS-V Algorithms: Fast, Collision-free Trajectory Planning for Heavily
    Overlapping Robotic Fiber Positioners, AJ 161, 92 (2021); kaiju (``sdss/kaiju``) and the
    SDSS-V FPS calibrations (``sdss/fps_calibrations``), ``docs/references.md``.
    """
    step = float(ang_step_deg)
    if not math.isfinite(step) or step < 0:
        raise InputError(f"ang_step_deg must be a finite number >= 0, got {ang_step_deg!r}", value=ang_step_deg)
    return 2 * geom.robot_buffer + 2 * math.sin(math.radians(step)) * sum(ROUGH_ARMS)
