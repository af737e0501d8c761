#!/usr/bin/env python
"""The kaiju side of the kaiju-vs-supcoord benchmark (run with kaiju's own venv only).

kaiju (PyPI ``sdss-kaiju`` 1.4.1, BSD-3, github.com/sdss/kaiju) is SDSS-V's path planner
for its alpha-beta fibre robots.  This script drives kaiju exactly as kaiju and SDSS's
robot-control software jaeger (``src/jaeger/kaiju.py``, ``etc/jaeger_APO.yml``) drive it,
and writes plain JSON that supcoord (or anything else) can read without kaiju::

    PY=$KAIJU_PYTHON   # a venv with kaiju: ../shared/tools/install-kaiju.sh PYTHON
    $PY benchmarks/kaiju_side.py instances --out DIR --seeds 10 --grids hex61,hex127,hex547,apo,lco
    $PY benchmarks/kaiju_side.py plan --instance DIR/hex61_s0.json --planner greedy \
        --direction fold --out PATH.json
    $PY benchmarks/kaiju_side.py replay --instance DIR/hex61_s0.json --angles PLAN.json \
        --out REPLAY.json [--buffer 1.92] [--steps]
    $PY benchmarks/kaiju_side.py field --problem PROBLEM.json --out DIR/apo-field_s0.json
    $PY benchmarks/kaiju_side.py jaeger --instance DIR/hex127_s0.json --direction direct \
        --out JAEGER.json [--planner mdp] [--retries 5] [--force] [--max-wall S]

``field`` makes an instance from a supcoord PROBLEM.json on a wok (its targets, and its
``offline`` robots held as jaeger's ``get_robot_grid`` holds a disabled positioner: start =
destination, ``isOffline``). ``jaeger`` runs jaeger 1.9.1's decollision and deadlock resolution
(``jaeger_deadlocks.py``, which cites jaeger's source) over kaiju's planner and writes the robots
left on their targets.

What kaiju does (file:line in sdss/kaiju 1.4.1, the installed version)
------------------------------------------------------------------------
* Grids.  ``hexN``: ``kaiju.utils.hexFromDia(nDia, pitch=22.4)`` (utils.py:251, rows
  sorted lower-left first), N = 1 + 3R(R+1) robots with nDia = 2R + 1 (61: 9, 127: 13,
  547: 27); every robot added with ``RobotGrid.addRobot(id, str(id), [x, y, 0], True)``
  and kaiju's defaults (robotGrid.py:399-438): alpha arm ``coordio.defaults.ALPHA_LEN``
  7.4 mm, fibres ``MET_BETA_XY`` (14.314, 0), ``BOSS_BETA_XY`` (14.965, -0.376),
  ``AP_BETA_XY`` (14.965, 0.376), orientation ``IHAT, JHAT, KHAT`` = (0,-1,0), (1,0,0),
  (0,0,1), element height 143.1 mm, collision buffer 2.0 mm and the beta collision
  segment from (0, 0) to (BETA_LEN - dxTip, 0) in the beta-arm frame with BETA_LEN 16.2 mm
  and dxTip = sqrt(buffer^2 + 0.3^2) - 0.55 (robotGrid.py:410-426), i.e. 14.7276 mm.
  ``apo``: ``RobotGridAPO`` (robotGrid.py:1241) = ``_load_from_tables`` (robotGrid.py:1090)
  on the APO tables of ``sdss/fps_calibrations`` (``apo/wok_calibs/sloanFlatCMM``; a copy
  in ``../shared/instruments/sdss-v`` beside the checkout): 500 robots with their measured alpha arm,
  fibre positions, alpha/beta offsets and dx/dy, buffer 2 (robotGrid.py:1112), 60
  fiducials with buffer 3 (robotGrid.py:1115-1120), 6 GFA segments hard-coded in kaiju with
  buffer 3 (robotGrid.py:1124-1152) and ``fiducialWatch`` robots (robotGrid.py:1154-1180).
  ``lco``: ``RobotGridLCO`` (robotGrid.py:1252), the same on the LCO tables
  (``lco/wok_calibs/duPontFlatCMM``); coordio reads both sites' tables (``WOKCALIB_DIR`` lists
  one directory per site).
* Step and tolerance as jaeger runs kaiju (jaeger_APO.yml ``kaiju``): ``RobotGrid(stepSize=
  0.1, epsilon=0.1*2, seed)``, ``setCollisionBuffer(2.0)``, folded lattice
  (alpha, beta) = (10, 170) deg, speed 2 RPM = 12 deg/s, smooth_points 21, greed 0.7,
  phobia 0.6, default generator ``mdp`` = ``pathGenMDP2``.
* Random decollided targets: ``robot.setXYUniform()`` for every robot (robot.cpp:306-327:
  a point uniform in the annulus [met_x - alphaLen, met_x + alphaLen] around the alpha axis,
  inverse kinematics for the metrology fibre, right-handed) then ``decollideGrid()``
  (robotGrid.cpp:199-225: while any robot is kaiju-collided, redraw every collided robot with
  ``setXYUniform`` up to 1000 times), exactly the first half of kaiju's
  ``getRandomPathPair`` (robotGrid.py:129-170).  The C ``rand()`` stream is seeded by
  ``RobotGrid(seed=...)`` (``srand(seed)``, robotGrid.cpp:28); benchmark seed s uses kaiju seed
  s + 1 because glibc's ``srand(0)`` equals ``srand(1)`` (seeds 0 and 1 would coincide).
* Collision verdict ``isCollided`` (robotGrid.cpp:698-712): robot-robot when the distance
  between the two beta collision segments < b1 + b2 + maxDisplacement (robotGrid.cpp:799-824;
  maxDisplacement = 2 sin(angStep) (7.4 + 15) mm, robotGrid.cpp:32, 0.0782 mm at 0.1 deg);
  robot-fiducial when point-segment distance < b_robot + b_fid (robotGrid.cpp:826-846);
  fiducialWatch robots are also "collided" when beta < 41.2853 - 1.3085 alpha
  (robotGrid.cpp:22-23, 851-855); robot-GFA when segment distance < b_robot + b_gfa
  (robotGrid.cpp:861-883).
* Fold (as SDSS uses kaiju, jaeger configuration.py / kaiju.py ``get_path_pair``): robots
  at their targets, destination = lattice, ``pathGenGreedy()`` (robotGrid.cpp:388-468) or
  ``pathGenMDP2(greed, phobia)`` (robotGrid.cpp:1412-1535); every step each robot moves each
  joint by -angStep, 0 or +angStep (robotGrid.cpp:35-42); ``didFail`` is False iff every
  robot reached its destination within maxPathSteps = ceil(1000/angStep) steps.  Unfold =
  the fold path reversed in time (``getPathPair`` returns it as ``fromDestination``,
  robotGrid.py:273-279).  Direct: robots at the lattice, destination = targets.
* Time: kaiju's timestep is dt = angStep / (speed_rpm * 360 / 60) s (robotGrid.py:210-211,
  251, 269); a raw path of nSteps points lasts nSteps * dt.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

# jaeger's production settings (sdss/jaeger src/jaeger/etc/jaeger_APO.yml, key "kaiju")
ANG_STEP = 0.1
EPSILON_FACTOR = 2.0
COLLISION_BUFFER = 2.0
LATTICE = (10.0, 170.0)
SPEED_RPM = 2.0
SMOOTH_POINTS = 21
COLLISION_SHRINK = 0.08
GREED = 0.7
PHOBIA = 0.6
MDP2_TRIES = 5
PITCH = 22.4
HEX_DIA = {"hex61": 9, "hex127": 13, "hex547": 27}
#: the real woks: grid name -> the tables' file prefix, and their fps_calibrations directories
SITES = {"apo": "apo", "lco": "lco"}
CALIB_DIRS = {"apo": "sloanFlatCMM", "lco": "duPontFlatCMM"}
SHARED_CALIB = str(Path(__file__).resolve().parents[2] / "shared" / "instruments" / "sdss-v")
FWC0, FWC1 = 41.2853, -1.3085  # robotGrid.cpp:22-23

def _fail(msg: str):
    """A user error: one line on stderr, exit status 2 (as supcoord's commands)."""
    print(f"kaiju_side: error: {msg}", file=sys.stderr)
    sys.exit(2)


_K = None  # the kaiju modules, imported lazily (WOKCALIB_DIR must be set first)


def _portable(paths: str) -> str:
    """Paths (``:``-separated) as a results file records them, without this machine's directories:
    relative to the repository inside it, else ``$TMPDIR/`` (the temporary directory) or ``$DIR/``
    and the file name."""
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    tmp = os.path.abspath(tempfile.gettempdir())
    out = []
    for path in paths.split(":"):
        real = os.path.abspath(path)
        if real.startswith(repo + os.sep):
            out.append(os.path.relpath(real, repo))
        elif real.startswith(tmp + os.sep):
            out.append("$TMPDIR/" + os.path.relpath(real, tmp))
        else:
            out.append("$DIR/" + os.path.basename(real))
    return ":".join(out)


def _kaiju(wokcalib: str | None = None):
    """Import kaiju with coordio's calibration pointed at the APO and LCO tables (coordio
    concatenates the directories listed in ``WOKCALIB_DIR``, one per site)."""
    global _K
    if _K is not None:
        return _K
    if wokcalib is None:
        wokcalib = os.environ.get("WOKCALIB_DIR")
    if not wokcalib:
        dirs = []
        for site in SITES.values():
            path = os.path.join(tempfile.gettempdir(), f"kaiju_side_wokcalib_{site}")
            os.makedirs(path, exist_ok=True)
            for name in ("positionerTable", "wokCoords", "fiducialCoords", "gfaCoords"):
                link = os.path.join(path, name + ".csv")
                if not os.path.exists(link):
                    os.symlink(os.path.join(SHARED_CALIB, f"{site}_{name}.csv"), link)
            dirs.append(path)
        wokcalib = ":".join(dirs)
    os.environ["WOKCALIB_DIR"] = wokcalib
    warnings.simplefilter("ignore")
    import coordio
    import coordio.defaults as cdef
    import kaiju
    import kaiju.robotGrid as krg
    import kaiju.utils as kutils

    _K = {"kaiju": kaiju, "rg": krg, "utils": kutils, "cdef": cdef, "coordio": coordio,
          "wokcalib": wokcalib}
    return _K


@contextlib.contextmanager
def _stdout_to_stderr():
    """kaiju's C++ (pathGenMDP2) prints to fd 1; keep our stdout clean."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        os.dup2(2, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def _seg_beta_xy(buffer: float, beta_len: float) -> list[list[float]]:
    """kaiju's default beta collision segment (robotGrid.py:410-426)."""
    tip_flat, corner = 0.6, 0.55
    dx_tip = math.sqrt(buffer ** 2 + (tip_flat / 2) ** 2) - corner
    return [[0.0, 0.0], [beta_len - dx_tip, 0.0]]


def build_grid(kind: str, seed: int, ang_step: float = ANG_STEP, buffer: float = COLLISION_BUFFER):
    """A kaiju grid as kaiju builds it; returns (grid, per-robot static geometry dict)."""
    K = _kaiju()
    cdef = K["cdef"]
    eps = ang_step * EPSILON_FACTOR
    geo: dict[int, dict] = {}
    if kind in HEX_DIA:
        rg = K["rg"].RobotGrid(stepSize=ang_step, epsilon=eps, seed=seed)
        xs, ys = K["utils"].hexFromDia(HEX_DIA[kind], pitch=PITCH)
        for rid, (x, y) in enumerate(zip(xs, ys)):
            rg.addRobot(rid, str(rid), [float(x), float(y), 0.0], True)
            geo[rid] = {"alpha_arm_mm": float(cdef.ALPHA_LEN),
                        "met_beta_xy_mm": list(map(float, cdef.MET_BETA_XY)),
                        "boss_beta_xy_mm": list(map(float, cdef.BOSS_BETA_XY)),
                        "ap_beta_xy_mm": list(map(float, cdef.AP_BETA_XY)),
                        "collision_seg_beta_xy_mm": _seg_beta_xy(2.0, float(cdef.BETA_LEN))}
        rg.initGrid()
    elif kind in SITES:
        grid_class = K["rg"].RobotGridAPO if kind == "apo" else K["rg"].RobotGridLCO
        rg = grid_class(stepSize=ang_step, epsilon=eps, seed=seed)
        pt = cdef.calibration.positionerTable.loc[kind.upper()].reset_index()
        for _, row in pt.iterrows():
            geo[int(row.positionerID)] = {
                "alpha_arm_mm": float(row.alphaArmLen),
                "met_beta_xy_mm": [float(row.metX), float(row.metY)],
                "boss_beta_xy_mm": [float(row.bossX), float(row.bossY)],
                "ap_beta_xy_mm": [float(row.apX), float(row.apY)],
                "collision_seg_beta_xy_mm": _seg_beta_xy(2.0, float(cdef.BETA_LEN)),
                "table_row": int(_)}
    else:
        _fail(f"unknown grid {kind!r} (hex61, hex127, hex547, apo, lco)")
    rg.setCollisionBuffer(buffer)  # as jaeger's get_robot_grid
    return rg, geo


def robot_order(rg, kind: str, geo: dict) -> list[int]:
    """Instance robot order: hex = kaiju id (hexFromDia order); apo, lco = calibration table rows."""
    if kind in SITES:
        return sorted(rg.robotDict, key=lambda rid: geo[rid]["table_row"])
    return sorted(rg.robotDict)


def _planar_model(robot, geo: dict) -> dict:
    """Exact planar form of kaiju's forward kinematics for one robot (verified below).

    kaiju: tangent = positionerToTangent(alpha, beta, p) (conv.cpp:229-255) with
    elbow = L (cos(a + aOff), sin(a + aOff)) and p at angle a + b + atan2(py, px) + bOff + aOff,
    then wok = tangentToWok(tangent) (conv.cpp:116-156), which for a flat wok is
    wok_xy = origin + M @ tangent_xy.
    """
    L = geo["alpha_arm_mm"]
    aoff = robot.alphaOffDeg
    ab0 = (robot.alpha, robot.beta)

    def elbow(a):
        robot.setAlphaBeta(a, 0.0)
        return np.array(robot.collisionSegWokXYZ[0][:2])

    e0, e90, e180 = elbow(-aoff), elbow(90.0 - aoff), elbow(180.0 - aoff)
    origin = (e0 + e180) / 2
    m = np.column_stack([(e0 - origin) / L, (e90 - origin) / L])
    robot.setAlphaBeta(*ab0)
    return {"origin_xy_mm": origin.tolist(), "tangent_to_wok_matrix": m.tolist(),
            "alpha_zero_wok_deg": math.degrees(math.atan2(*(m @ [math.cos(math.radians(aoff)),
                                                                  math.sin(math.radians(aoff))])[::-1])),
            "ccw": bool(np.linalg.det(m) > 0)}


def planar_points(pm: dict, geo: dict, aoff: float, boff: float, alpha: float, beta: float,
                  p_beta_xy) -> np.ndarray:
    """wok xy of beta-frame point p with the planar model (for checking; same as kaiju)."""
    a = math.radians(alpha + aoff)
    px, py = p_beta_xy
    t = math.radians(alpha + beta + boff + aoff) + math.atan2(py, px)
    r = math.hypot(px, py)
    tan = np.array([geo["alpha_arm_mm"] * math.cos(a) + r * math.cos(t),
                    geo["alpha_arm_mm"] * math.sin(a) + r * math.sin(t)])
    return np.array(pm["origin_xy_mm"]) + np.array(pm["tangent_to_wok_matrix"]) @ tan


# --------------------------------------------------------------------------- instances


def kaiju_seed(seed: int) -> int:
    """The RobotGrid seed of benchmark seed ``seed``: seed + 1, because kaiju seeds C's rand() with
    srand(seed) (robotGrid.cpp:28) and glibc's srand(0) is srand(1): seeds 0 and 1 would give the
    same instance."""
    return int(seed) + 1


def make_instance(kind: str, seed: int, field: dict | None = None) -> dict:
    """An instance: kaiju's random decollided targets, or ``field``'s (a supcoord PROBLEM.json on
    the wok: ``target.alpha_beta_deg`` in table row order and ``offline`` ``{row: [α, β]}``)."""
    K = _kaiju()
    rg, geo = build_grid(kind, kaiju_seed(seed))
    order = robot_order(rg, kind, geo)
    t0 = time.perf_counter()
    offline = {}
    if field is None:
        # kaiju's random decollided targets (first half of getRandomPathPair, robotGrid.py:154-169)
        for robot in rg.robotDict.values():
            robot.setDestinationAlphaBeta(*LATTICE)
            robot.setXYUniform()
        n_initial = rg.getNCollisions()
        rg.decollideGrid()
    else:
        offline = {order[int(k)]: list(map(float, v)) for k, v in field.get("offline", {}).items()}
        for rid, ab in zip(order, field["target"]["alpha_beta_deg"]):
            ab = offline.get(rid, ab)
            rg.robotDict[rid].setAlphaBeta(float(ab[0]), float(ab[1]))
            rg.robotDict[rid].setDestinationAlphaBeta(*(ab if rid in offline else LATTICE))
            rg.robotDict[rid].isOffline = rid in offline
        n_initial = rg.getNCollisions()
        if n_initial:
            _fail(f"the field's targets are kaiju-collided: robots {sorted(rg.getCollidedRobotList())[:20]}")
    t_dec = time.perf_counter() - t0
    assert rg.getNCollisions() == 0
    targets = {rid: (rg.robotDict[rid].alpha, rg.robotDict[rid].beta) for rid in order}
    tgt_xy = {rid: list(rg.robotDict[rid].metWokXYZ[:2]) for rid in order}
    tgt_boss = {rid: list(rg.robotDict[rid].bossWokXYZ[:2]) for rid in order}
    tgt_ap = {rid: list(rg.robotDict[rid].apWokXYZ[:2]) for rid in order}
    # planar model per robot, checked against kaiju's own wok coordinates
    robots, max_err = [], 0.0
    rng = np.random.default_rng(seed)
    z_values = set()
    for rid in order:
        r = rg.robotDict[rid]
        g = geo[rid]
        pm = _planar_model(r, g)
        for a, b in rng.uniform([0, 0], [360, 180], size=(3, 2)).tolist() + [list(targets[rid])]:
            r.setAlphaBeta(a, b)
            seg = np.array(r.collisionSegWokXYZ)
            z_values.update(np.round(seg[:, 2], 9).tolist())
            for p, kaiju_xy in ((g["collision_seg_beta_xy_mm"][1], seg[1, :2]),
                                (g["met_beta_xy_mm"], np.array(r.metWokXYZ[:2])),
                                (g["collision_seg_beta_xy_mm"][0], seg[0, :2])):
                err = np.abs(planar_points(pm, g, r.alphaOffDeg, r.betaOffDeg, a, b, p) - kaiju_xy).max()
                max_err = max(max_err, float(err))
        r.setAlphaBeta(*targets[rid])
        robots.append({
            "id": int(rid), "hole_id": r.holeID,
            "base_xyz_mm": list(map(float, r.basePos)),
            "alpha_arm_mm": g["alpha_arm_mm"],
            "alpha_offset_deg": float(r.alphaOffDeg), "beta_offset_deg": float(r.betaOffDeg),
            "dxyz_mm": list(map(float, r.dxyz)),
            "ihat": list(map(float, r.iHat)), "jhat": list(map(float, r.jHat)),
            "khat": list(map(float, r.kHat)),
            "element_height_mm": float(r.elementHeight), "scale_fac": float(r.scaleFac),
            "collision_seg_beta_xy_mm": g["collision_seg_beta_xy_mm"],
            "collision_buffer_mm": float(r.collisionBuffer),
            "met_beta_xy_mm": g["met_beta_xy_mm"], "boss_beta_xy_mm": g["boss_beta_xy_mm"],
            "ap_beta_xy_mm": g["ap_beta_xy_mm"],
            "has_apogee": bool(r.hasApogee), "lefthanded": bool(r.lefthanded),
            "fiducial_watch": bool(r.fiducialWatch),
            "robot_neighbors": sorted(int(x) for x in r.robotNeighbors),
            "planar": pm,
        })
    # the folded lattice is collision-free?
    for rid, r in rg.robotDict.items():
        r.setAlphaBeta(*offline.get(rid, LATTICE))
    n_folded = rg.getNCollisions()
    for rid in order:
        rg.robotDict[rid].setAlphaBeta(*targets[rid])
    fiducials = [{"id": int(f.id), "xyz_mm": list(map(float, f.xyzWok)),
                  "buffer_mm": float(f.collisionBuffer)} for f in rg.fiducialDict.values()]
    gfas = [{"id": int(g.id), "segment_xyz_mm": [list(map(float, p)) for p in g.collisionSegWokXYZ],
             "buffer_mm": float(g.collisionBuffer)} for g in rg.gfaDict.values()]
    inst = {
        "format": "supcoord-benchmark/kaiju-instance/1",
        "grid": kind, "kind": "hex" if kind in HEX_DIA else "instrument",
        "seed": seed, "kaiju_seed": kaiju_seed(seed),
        "kaiju_version": K["kaiju"].__version__, "coordio_version": K["coordio"].__version__,
        "builder": (f"kaiju.utils.hexFromDia({HEX_DIA[kind]}, pitch={PITCH}) + RobotGrid.addRobot("
                    "id, str(id), [x, y, 0], True) defaults; initGrid(); setCollisionBuffer(2.0)"
                    if kind in HEX_DIA else
                    f"kaiju.robotGrid.RobotGrid{kind.upper()} on sdss/fps_calibrations {kind}/wok_calibs/"
                    f"{CALIB_DIRS[kind]} (release 2025.12.04, commit e7867464); setCollisionBuffer(2.0)"),
        "robot_order": ("kaiju robot id = hexFromDia order (lower-left first, row by row)"
                        if kind in HEX_DIA else f"rows of positionerTable.csv ({kind.upper()})"),
        "ang_step_deg": ANG_STEP, "epsilon": ANG_STEP * EPSILON_FACTOR,
        "max_displacement_mm": float(rg.maxDisplacement),
        "max_path_steps": int(rg.maxPathSteps),
        "collision_buffer_mm": COLLISION_BUFFER,
        "folded_lattice_deg": list(LATTICE),
        "fibre_used": "metrology (setXYUniform samples the metrology fibre, robot.cpp:306-327)",
        "robot_ids": [int(r) for r in order],
        "hole_ids": [rg.robotDict[r].holeID for r in order],
        "base_xy_mm": [[float(rg.robotDict[r].xPos), float(rg.robotDict[r].yPos)] for r in order],
        "alpha_axis_xy_mm": [rb["planar"]["origin_xy_mm"] for rb in robots],
        "alpha_zero_wok_deg": [rb["planar"]["alpha_zero_wok_deg"] for rb in robots],
        "frame_note": ("base_xy_mm is kaiju's robot.xPos/yPos (the hole centre; kaiju's neighbour lists use "
                       "it); the alpha axis is alpha_axis_xy_mm (hole + calibration dx, dy through the "
                       "hole's i/j vectors; equal to base_xy_mm on hex grids). alpha = 0 points along "
                       "alpha_zero_wok_deg in the wok frame (kaiju's default orientation IHAT = (0,-1,0): "
                       "-90 deg, i.e. wok -y, plus the robot's alpha offset); alpha and beta turn "
                       "counter-clockwise; the beta arm's angle is alpha_zero + alpha + beta + beta_offset"),
        "robots": robots,
        "obstacles": {"fiducials": fiducials, "gfas": gfas},
        "fiducial_watch_rule": {"c0": FWC0, "c1": FWC1,
                                "rule": "robot with fiducial_watch is collided when beta < c0 + c1*alpha "
                                        "(robotGrid.cpp:851-855)"},
        "collision_rules": {
            "robot_robot": "dist(seg1, seg2) < b1 + b2 + max_displacement_mm (robotGrid.cpp:813)",
            "robot_fiducial": "dist(fiducial point, seg) < b_robot + b_fiducial (robotGrid.cpp:839)",
            "robot_gfa": "dist(gfa seg, seg) < b_robot + b_gfa (robotGrid.cpp:874)",
            "segment": "beta collision segment in wok coordinates: collision_seg_beta_xy_mm through the "
                       "robot's forward kinematics (robot.cpp:142-159)"},
        "kinematics": ("tangent = (L cos(a+aOff) + r cos(a+b+aOff+bOff+atan2(py,px)), "
                       "L sin(a+aOff) + r sin(a+b+aOff+bOff+atan2(py,px))) for a beta-frame point "
                       "(px,py), r = hypot(px,py) (coordio positionerToTangent); wok_xy = "
                       "planar.origin_xy_mm + planar.tangent_to_wok_matrix @ tangent"),
        "planar_model_max_error_mm": max_err,
        "segment_z_mm": sorted(z_values),
        "folded_deg": [list(offline.get(r, LATTICE)) for r in order],
        "offline": {str(i): offline[r] for i, r in enumerate(order) if r in offline},
        "targets_deg": [list(targets[r]) for r in order],
        "targets_xy_mm": [tgt_xy[r] for r in order],
        "targets_boss_xy_mm": [tgt_boss[r] for r in order],
        "targets_apogee_xy_mm": [tgt_ap[r] for r in order],
        "target_generation": ("RobotGrid(seed=kaiju_seed): robot.setXYUniform() for every robot in id order, "
                              "then decollideGrid() (kaiju getRandomPathPair, robotGrid.py:154-169)"
                              if field is None else "given by a supcoord PROBLEM.json (kaiju_side.py field)"),
        "checks": {"initial_kaiju_collided_robots": int(n_initial),
                   "targets_kaiju_collided_robots": 0,
                   "folded_kaiju_collided_robots": int(n_folded),
                   "decollide_seconds": t_dec},
    }
    if kind in SITES:
        inst["fps_calibrations"] = {"release": "2025.12.04",
                                    "commit": "e7867464fe410188e8aa93cbcbd4eb113afed005",
                                    "dir": f"{kind}/wok_calibs/{CALIB_DIRS[kind]}",
                                    "WOKCALIB_DIR": _portable(K["wokcalib"])}
    return inst


def cmd_instances(args) -> None:
    os.makedirs(args.out, exist_ok=True)
    for kind in args.grids.split(","):
        for seed in range(args.seeds):
            t0 = time.perf_counter()
            inst = make_instance(kind, seed)
            path = os.path.join(args.out, f"{kind}_s{seed}.json")
            with open(path, "w") as f:
                json.dump(inst, f)
            print(f"{path}: {len(inst['robot_ids'])} robots, "
                  f"planar err {inst['planar_model_max_error_mm']:.2e} mm, "
                  f"{time.perf_counter() - t0:.2f} s", file=sys.stderr)


# --------------------------------------------------------------------------- plan


def load_instance(path: str) -> dict:
    with open(path) as f:
        return json.load(f)


def grid_for(inst: dict, seed: int | None = None, ang_step: float | None = None):
    rg, geo = build_grid(inst["grid"], inst["kaiju_seed"] if seed is None else seed,
                         ang_step or inst["ang_step_deg"])
    order = robot_order(rg, inst["grid"], geo)
    if order != inst["robot_ids"]:
        _fail("instance robots differ from kaiju's grid")
    return rg, order


def _breakpoints(path: list) -> list[list[float]]:
    """Lossless compression of a piecewise-linear [[step, deg], ...] path to its corners."""
    pts = [[float(s), float(v)] for s, v in path]
    if len(pts) <= 2:
        return pts
    out = [pts[0]]
    for i in range(1, len(pts) - 1):
        (s0, v0), (s1, v1), (s2, v2) = out[-1], pts[i], pts[i + 1]
        if abs((v1 - v0) * (s2 - s0) - (v2 - v0) * (s1 - s0)) > 1e-9 * max(1.0, s2 - s0):
            out.append(pts[i])
    out.append(pts[-1])
    return out


def set_offline(rg, order: list[int], inst: dict, start: dict, dest: dict) -> None:
    """The instance's offline robots (``offline``: row -> [alpha, beta]) held where they are, as jaeger's
    ``get_robot_grid`` holds a disabled positioner: start = destination = its angles, ``isOffline``."""
    for row, ab in inst.get("offline", {}).items():
        rid = order[int(row)]
        start[rid] = dest[rid] = tuple(ab)
        rg.robotDict[rid].isOffline = True


def run_planner(rg, planner: str, greed: float = GREED, phobia: float = PHOBIA) -> dict:
    """kaiju's path generation as jaeger's ``get_path_pair`` calls it; the call made."""
    if planner == "greedy":
        rg.pathGenGreedy()
        return {"call": "pathGenGreedy(stopIfDeadlock=False, ignoreInitialCollisions=False)"}
    if planner == "mdp":
        rg.pathGenMDP2(greed, phobia, False, MDP2_TRIES)
        return {"call": f"pathGenMDP2(greed={greed}, phobia={phobia}, "
                        f"ignoreInitialCollisions=False, nTries={MDP2_TRIES})",
                "mdp2_iterations": int(rg.mdp2iter)}
    if planner == "mdp1":
        rg.pathGenMDP(greed, phobia)
        return {"call": f"pathGenMDP(greed={greed}, phobia={phobia})"}
    _fail(f"unknown planner {planner}")


def cmd_plan(args) -> None:
    inst = load_instance(args.instance)
    seed = inst["kaiju_seed"] if args.plan_seed is None else args.plan_seed
    rg, order = grid_for(inst, seed)
    lattice = inst["folded_lattice_deg"]
    targets = {rid: ab for rid, ab in zip(order, inst["targets_deg"])}
    if args.direction in ("fold", "unfold"):
        start = targets
        dest = {rid: lattice for rid in order}
    else:  # direct
        start = {rid: lattice for rid in order}
        dest = targets
    set_offline(rg, order, inst, start, dest)
    for rid in order:
        r = rg.robotDict[rid]
        r.setAlphaBeta(*start[rid])
        r.setDestinationAlphaBeta(*dest[rid])
    if rg.getNCollisions():
        _fail("start configuration is kaiju-collided")
    with _stdout_to_stderr():
        c0, w0 = time.process_time(), time.perf_counter()
        params = run_planner(rg, args.planner, args.greed, args.phobia)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    did_fail = bool(rg.didFail)
    deadlocked = sorted(int(x) for x in rg.deadlockedRobots())
    off_target = [int(rid) for rid in order if rg.robotDict[rid].score() != 0]
    speed_dps = SPEED_RPM * 360.0 / 60.0
    dt = rg.angStep / speed_dps
    n_steps = int(rg.nSteps)
    # raw path (what kaiju planned and collision-checked step by step)
    raw = {}
    for rid in order:
        r = rg.robotDict[rid]
        raw[rid] = {"alpha": _breakpoints(r.alphaPath), "beta": _breakpoints(r.betaPath)}
    smoothed = None
    if not args.no_smooth and not did_fail:  # jaeger smooths only a successful plan (kaiju.py:344-348)
        with _stdout_to_stderr():
            to_dest, from_dest = rg.getPathPair(speed=SPEED_RPM, smoothPoints=SMOOTH_POINTS,
                                                collisionShrink=COLLISION_SHRINK, pathDelay=0)
        smoothed, smoothed_back = {}, {}
        for rid in order:
            src, back = (to_dest[rid], from_dest[rid]) if args.direction != "unfold" else (from_dest[rid], to_dest[rid])
            smoothed[rid] = {ax: [[float(t), float(d)] for d, t in src[ax]] for ax in ("alpha", "beta")}
            smoothed_back[rid] = {ax: [[float(t), float(d)] for d, t in back[ax]] for ax in ("alpha", "beta")}
    t_end = (n_steps - 1) * dt

    def timed(bp):
        return [[s * dt, v] for s, v in bp]

    path = {}
    for rid in order:
        p = {ax: timed(raw[rid][ax]) for ax in ("alpha", "beta")}
        if args.direction == "unfold":
            p = {ax: [[t_end - t, v] for t, v in reversed(pts)] for ax, pts in p.items()}
        path[str(rid)] = p
    solved = (not did_fail) and not off_target
    out = {
        "format": "supcoord-benchmark/kaiju-plan/1",
        "instance": _portable(args.instance), "grid": inst["grid"], "seed": inst["seed"],
        "plan_seed": seed,
        "planner": args.planner, "planner_params": params, "direction": args.direction,
        "kaiju_version": inst["kaiju_version"],
        "solved": solved, "did_fail": did_fail,
        "deadlocked": deadlocked,
        "deadlocked_note": "kaiju deadlockedRobots(): robots not at destination or, at destination, "
                           "with a neighbour within b1+b2+3*maxDisplacement (robotGrid.cpp:978-999)",
        "off_target": off_target,
        "cpu_seconds": cpu, "wall_seconds": wall,
        "planning_note": ("unfold = the fold plan reversed in time (kaiju's fromDestination); "
                          "its timings are the fold's" if args.direction == "unfold" else ""),
        "ang_step_deg": float(rg.angStep), "speed_rpm": SPEED_RPM, "speed_deg_per_s": speed_dps,
        "timestep_s": dt, "n_steps": n_steps, "motion_time_s": n_steps * dt,
        "last_raw_time_s": t_end,
        "collision_buffer_mm": inst["collision_buffer_mm"],
        "robot_ids": order,
        "start_deg": [list(start[r]) for r in order] if args.direction != "unfold"
        else [list(dest[r]) for r in order],
        "end_deg": [list(dest[r]) for r in order] if args.direction != "unfold"
        else [list(start[r]) for r in order],
        "path_kind": "raw",
        "path_note": ("raw = kaiju's rough path (robot.alphaPath/betaPath: one point per step, every "
                      "joint moves -angStep/0/+angStep per step, collision-checked by kaiju at every "
                      "step), here reduced losslessly to its corners; t = step * timestep_s"),
        "path": path,
    }
    if smoothed is not None:
        last = max(pts[-1][0] for p in smoothed.values() for pts in p.values())
        out["path_smoothed"] = {str(r): smoothed[r] for r in order}
        out["path_smoothed_note"] = (f"kaiju getPathPair(speed={SPEED_RPM}, smoothPoints={SMOOTH_POINTS}, "
                                     "pathDelay=0): Savitzky-Golay smoothed + RDP simplified (epsilon = "
                                     f"{rg.epsilon}); what jaeger sends to the robots (after a 1 s "
                                     "pathDelay); NOT collision-checked by kaiju 1.4.1 "
                                     "(verifySmoothed is commented out, robotGrid.py:281-283)")
        out["motion_time_smoothed_s"] = last
        out["path_smoothed_back"] = {str(r): smoothed_back[r] for r in order}
        out["path_smoothed_back_note"] = ("the other path of the same getPathPair call (fromDestination for "
                                          "fold, toDestination for unfold): the way back, as jaeger sends it")
        out["motion_time_smoothed_back_s"] = max(pts[-1][0] for p in smoothed_back.values() for pts in p.values())
    with open(args.out, "w") as f:
        json.dump(out, f)
    print(json.dumps({k: out[k] for k in ("grid", "seed", "planner", "direction", "solved",
                                          "cpu_seconds", "wall_seconds", "n_steps", "motion_time_s")}
                     | {"deadlocked": len(deadlocked), "off_target": len(off_target)}))


# --------------------------------------------------------------------------- jaeger


class JaegerGrid:
    """jaeger's handling of kaiju's grid (``jaeger_deadlocks.Grid``) on an instance.

    The live grid holds the robots at their targets, destination the folded lattice, offline
    robots held (jaeger ``get_robot_grid``); ``save`` is jaeger's ``dump_robot_grid``, ``restore``
    its ``load_robot_grid`` (a new grid), ``plan`` its ``get_path_pair(data=dump)`` (a new grid
    from the dump, then kaiju's planner). ``direction`` ``fold`` plans as jaeger does (targets ->
    lattice; jaeger runs the path backwards); ``direct`` plans lattice -> targets on the same
    bookkeeping (the deadlock resolution then moves targets of a plan kaiju makes forwards).
    jaeger seeds every new grid from the clock; here grid k gets seed ``seed * 1000 + k``.
    """

    def __init__(self, inst: dict, planner: str, direction: str, seed: int, max_wall: float | None = None):
        self.inst, self.planner, self.direction, self.seed = inst, planner, direction, seed
        self.deadline = None if max_wall is None else time.perf_counter() + max_wall
        self.lattice = tuple(inst["folded_lattice_deg"])
        self.n_grids = 0
        self.plans: list[dict] = []
        rg, self.order = grid_for(inst, self._next_seed())
        self.offline = {self.order[int(k)]: tuple(v) for k, v in inst.get("offline", {}).items()}
        self.dump = {rid: (*ab, *(self.offline.get(rid, self.lattice)), rid in self.offline)
                     for rid, ab in zip(self.order, inst["targets_deg"])}
        self.live = self._load(self.dump)

    def _next_seed(self) -> int:
        self.n_grids += 1
        return self.seed * 1000 + self.n_grids

    def _load(self, dump: dict, start_at_lattice: bool = False):
        rg, _ = grid_for(self.inst, self._next_seed())
        for rid, (a, b, da, db, off) in dump.items():
            r = rg.robotDict[rid]
            if start_at_lattice and not off:  # direct: from the lattice to the targets
                r.setAlphaBeta(*self.lattice)
                r.setDestinationAlphaBeta(a, b)
            else:
                r.setAlphaBeta(a, b)
                r.setDestinationAlphaBeta(da, db)
            r.isOffline = bool(off)
        return rg

    def robots(self) -> list[int]:
        return list(self.order)

    def is_offline(self, robot: int) -> bool:
        return bool(self.live.robotDict[robot].isOffline)

    def collided_robots(self) -> list[int]:
        return [int(r) for r in self.live.getCollidedRobotList()]

    def is_collided(self, robot: int) -> bool:
        return bool(self.live.isCollided(robot))

    def set_xy_uniform(self, robot: int) -> None:
        self.live.robotDict[robot].setXYUniform()

    def decollide_robot(self, robot: int) -> None:
        self.live.decollideRobot(robot)

    def save(self) -> None:
        self.dump = {rid: (r.alpha, r.beta, r.destinationAlpha, r.destinationBeta, bool(r.isOffline))
                     for rid, r in self.live.robotDict.items()}

    def restore(self) -> None:
        self.live = self._load(self.dump)

    def plan(self):
        from jaeger_deadlocks import PathResult, TimeLimit

        if self.plans and self.deadline is not None and time.perf_counter() > self.deadline:
            raise TimeLimit(f"time limit: stopped after {len(self.plans)} plans (the benchmark's limit, not jaeger's)")

        rg = self._load(self.dump, start_at_lattice=self.direction == "direct")
        if rg.getNCollisions():
            _fail("jaeger: the start of a plan is kaiju-collided")
        with _stdout_to_stderr():
            c0 = time.process_time()
            call = run_planner(rg, self.planner)
            cpu = time.process_time() - c0
        at = frozenset(int(rid) for rid, r in rg.robotDict.items() if r.score() == 0)
        res = PathResult(bool(rg.didFail), tuple(int(x) for x in rg.deadlockedRobots()), at)
        self.plans.append({"cpu_seconds": cpu, "did_fail": res.did_fail, "deadlocked": len(res.deadlocks),
                           "at_destination": len(at),
                           "at_destination_active": len(at - set(self.offline)), "n_steps": int(rg.nSteps), "call": call["call"]})
        return res


def cmd_jaeger(args) -> None:
    """jaeger's get_paths (decollide, _resolve_deadlocks) on an instance; writes the outcome."""
    import numpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from jaeger_deadlocks import get_paths

    inst = load_instance(args.instance)
    grid = JaegerGrid(inst, args.planner, args.direction, inst["kaiju_seed"] if args.seed is None else args.seed,
                      args.max_wall)
    rng = numpy.random.RandomState(args.choice_seed)
    c0, w0 = time.process_time(), time.perf_counter()
    out = get_paths(grid, rng, n_retries=args.retries, force=args.force)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    active = [r for r in grid.order if r not in grid.offline]
    res = {"format": "supcoord-benchmark/jaeger-resolution/1", "instance": _portable(args.instance),
           "grid": inst["grid"], "seed": inst["seed"], "planner": args.planner, "direction": args.direction,
           "n_retries": args.retries, "force": args.force, "choice_seed": args.choice_seed,
           "jaeger_version": "1.9.1 (configuration.py get_paths/_resolve_deadlocks, kaiju.py decollide/get_path_pair)",
           "kaiju_version": inst["kaiju_version"],
           "robots": len(grid.order), "offline": len(grid.offline), "active": len(active),
           "error": out.error, "attempts": out.attempts, "plans": grid.plans,
           "decollided": out.decollided, "unlocked": out.unlocked, "offline_moved": out.offline_moved,
           "deadlocks_per_plan": out.deadlocks_per_attempt,
           "last_did_fail": out.last.did_fail if out.last else None,
           "on_target": len(out.on_target), "on_target_ids": out.on_target,
           "on_target_note": ("robots not offline, not moved by decollide/_resolve_deadlocks, at their "
                              "destination at the end of the last kaiju plan; when jaeger raises (error) it "
                              "runs nothing, and this is what the last plan would have given"),
           "cpu_seconds": cpu, "wall_seconds": wall}
    with open(args.out, "w") as f:
        json.dump(res, f, indent=1)
    print(json.dumps({k: res[k] for k in ("grid", "seed", "planner", "direction", "error", "attempts",
                                          "on_target", "active", "cpu_seconds")}))


def cmd_field(args) -> None:
    """A kaiju instance from a supcoord PROBLEM.json on the wok (its targets and offline robots)."""
    with open(args.problem) as f:
        prob = json.load(f)
    name = prob.get("layout", {}).get("name", "")
    kind = {"sdss-v-apo": "apo", "sdss-v-lco": "lco"}.get(name)
    if kind is None:
        _fail(f"{args.problem}: layout.name {name!r} is not sdss-v-apo or sdss-v-lco")
    inst = make_instance(kind, args.seed, field=prob)
    inst["field"] = {"problem": _portable(args.problem), "name": prob.get("name", "")}
    with open(args.out, "w") as f:
        json.dump(inst, f)
    print(f"{args.out}: {len(inst['robot_ids'])} robots, {len(inst['offline'])} offline", file=sys.stderr)


# --------------------------------------------------------------------------- replay


def seg_dist(p0, p1, q0, q1) -> np.ndarray:
    """Minimum distance between segments p0p1 and q0q1 (arrays (..., 3)), like kaiju's
    dist3D_Segment_to_Segment (utils.cpp:89) but exact and vectorised."""
    u, v, w = p1 - p0, q1 - q0, p0 - q0
    a = (u * u).sum(-1)
    b = (u * v).sum(-1)
    c = (v * v).sum(-1)
    d = (u * w).sum(-1)
    e = (v * w).sum(-1)
    D = a * c - b * b
    small = 1e-12
    sN = np.where(D < small, 0.0, b * e - c * d)
    sD = np.where(D < small, 1.0, D)
    tN = np.where(D < small, e, a * e - b * d)
    tD = np.where(D < small, c, D)
    # clamp s to [0, 1]
    neg = sN < 0
    sN = np.where(neg, 0.0, sN)
    tN = np.where(neg, e, tN)
    tD = np.where(neg, c, tD)
    big = sN > sD
    sN = np.where(big, sD, sN)
    tN = np.where(big, e + b, tN)
    tD = np.where(big, c, tD)
    # clamp t to [0, 1] and recompute s
    tneg = tN < 0
    tbig = tN > tD
    sN = np.where(tneg, np.clip(-d, 0, a), np.where(tbig, np.clip(-d + b, 0, a), sN))
    sD = np.where(tneg | tbig, np.where(a < small, 1.0, a), sD)
    tN = np.where(tneg, 0.0, np.where(tbig, tD, tN))
    sc = np.where(np.abs(sN) < small, 0.0, sN / sD)
    tc = np.where(np.abs(tN) < small, 0.0, tN / tD)
    dP = w + sc[..., None] * u - tc[..., None] * v
    return np.sqrt((dP * dP).sum(-1))


def point_seg_dist(pt, s0, s1) -> np.ndarray:
    v = s1 - s0
    w = pt - s0
    c1 = (w * v).sum(-1)
    c2 = (v * v).sum(-1)
    t = np.clip(np.where(c2 > 0, c1 / np.where(c2 > 0, c2, 1), 0), 0, 1)
    d = pt - (s0 + t[..., None] * v)
    return np.sqrt((d * d).sum(-1))


def trajectory_poses(trajs: list) -> np.ndarray:
    """The poses ``(K, n, 2)`` of timed trajectories (PLAN.json ``trajectories``: per robot
    ``{"alpha": [[t, deg], ...], "beta": [...]}``, linear in time between breakpoints, held
    before the first and after the last) at the union of their breakpoint times: between two
    consecutive times every joint turns linearly, so the poses between them are the straight
    line the replay interpolates."""
    times = np.unique(np.concatenate([np.asarray(r[j], float)[:, 0] for r in trajs for j in ("alpha", "beta")]))
    out = np.empty((len(times), len(trajs), 2))
    for i, r in enumerate(trajs):
        for j, name in enumerate(("alpha", "beta")):
            pts = np.asarray(r[name], float)
            out[:, i, j] = np.interp(times, pts[:, 0], pts[:, 1])
    return out


def cmd_replay(args) -> None:
    inst = load_instance(args.instance)
    with open(args.angles) as f:
        plan = json.load(f)
    trajs = plan.get("trajectories")
    if trajs and not args.steps:
        configs, replayed = trajectory_poses(trajs), "trajectories"
    else:
        configs, replayed = plan.get("angles_deg"), "angles_deg"
    if configs is None or not len(configs):
        _fail(f"{args.angles}: no angles_deg")
    configs = np.asarray(configs, dtype=float)
    rg, order = grid_for(inst, ang_step=args.ang_step or inst["ang_step_deg"])
    n = len(order)
    if configs.shape[1:] != (n, 2):
        _fail(f"{args.angles}: angles_deg has shape {configs.shape}, expected (k, {n}, 2)")
    if args.buffer is not None:
        rg.setCollisionBuffer(args.buffer)
    step = float(rg.angStep)
    robots = [rg.robotDict[r] for r in order]
    idx = {rid: i for i, rid in enumerate(order)}
    buf = np.array([r.collisionBuffer for r in robots])
    pairs = sorted({(min(i, idx[j]), max(i, idx[j])) for i, r in enumerate(robots)
                    for j in r.robotNeighbors})
    pairs = np.array(pairs, dtype=int).reshape(-1, 2)
    fid = [(i, f) for i, r in enumerate(robots) for f in r.fiducialNeighbors]
    gfa = [(i, g) for i, r in enumerate(robots) for g in r.gfaNeighbors]
    fid_xyz = np.array([rg.fiducialDict[f].xyzWok for _, f in fid]).reshape(-1, 3)
    fid_b = np.array([rg.fiducialDict[f].collisionBuffer for _, f in fid])
    fid_r = np.array([i for i, _ in fid], dtype=int)
    gfa_seg = np.array([rg.gfaDict[g].collisionSegWokXYZ for _, g in gfa]).reshape(-1, 2, 3)
    gfa_b = np.array([rg.gfaDict[g].collisionBuffer for _, g in gfa])
    gfa_r = np.array([i for i, _ in gfa], dtype=int)
    neigh = [{idx[j] for j in r.robotNeighbors} for r in robots]
    seg = np.zeros((n, 2, 3))
    cur = np.full((n, 2), np.nan)
    collided = np.zeros(n, dtype=bool)
    flagged_robots: set[int] = set()
    first_flag = None
    poses = flagged = 0
    mins = {"robot": math.inf, "fiducial": math.inf, "gfa": math.inf}
    worst = {"robot": None, "fiducial": None, "gfa": None}
    kinds = {"robot": 0, "fiducial": 0, "gfa": 0}
    t0 = time.perf_counter()

    def visit(pose: np.ndarray, where):
        nonlocal poses, flagged, first_flag
        moved = np.nonzero(np.any(pose != cur, axis=1))[0]
        for i in moved:
            robots[i].setAlphaBeta(float(pose[i, 0]), float(pose[i, 1]))
            seg[i] = robots[i].collisionSegWokXYZ
            cur[i] = pose[i]
        if len(moved):
            mv = np.zeros(n, dtype=bool)
            mv[moved] = True
            affected = set(moved.tolist())
            for i in moved:
                affected |= neigh[i]
            for i in affected:
                collided[i] = rg.isCollided(order[i])
            sel = pairs[mv[pairs[:, 0]] | mv[pairs[:, 1]]]
            if len(sel):
                d = seg_dist(seg[sel[:, 0], 0], seg[sel[:, 0], 1], seg[sel[:, 1], 0], seg[sel[:, 1], 1])
                d = d - buf[sel[:, 0]] - buf[sel[:, 1]]
                k = int(np.argmin(d))
                if d[k] < mins["robot"]:
                    mins["robot"] = float(d[k])
                    worst["robot"] = {"pose": poses, "at": where,
                                      "robots": [order[sel[k, 0]], order[sel[k, 1]]]}
            if len(fid_r):
                s = mv[fid_r]
                if s.any():
                    ri = fid_r[s]
                    d = point_seg_dist(fid_xyz[s], seg[ri, 0], seg[ri, 1]) - fid_b[s] - buf[ri]
                    k = int(np.argmin(d))
                    if d[k] < mins["fiducial"]:
                        mins["fiducial"] = float(d[k])
                        worst["fiducial"] = {"pose": poses, "at": where, "robot": order[ri[k]]}
            if len(gfa_r):
                s = mv[gfa_r]
                if s.any():
                    ri = gfa_r[s]
                    d = seg_dist(gfa_seg[s, 0], gfa_seg[s, 1], seg[ri, 0], seg[ri, 1]) - gfa_b[s] - buf[ri]
                    k = int(np.argmin(d))
                    if d[k] < mins["gfa"]:
                        mins["gfa"] = float(d[k])
                        worst["gfa"] = {"pose": poses, "at": where, "robot": order[ri[k]]}
        if collided.any():
            flagged += 1
            hit = np.nonzero(collided)[0]
            if first_flag is None:
                first_flag = {"pose": poses, "at": where, "robots": [order[i] for i in hit[:20]]}
            for i in hit:
                if i not in flagged_robots:
                    rid = order[i]
                    if rg.robotColliders(rid):
                        kinds["robot"] += 1
                    if rg.fiducialColliders(rid):
                        kinds["fiducial"] += 1
                    if rg.gfaColliders(rid):
                        kinds["gfa"] += 1
                flagged_robots.add(int(i))
        poses += 1

    visit(configs[0], [0, 0.0])
    for k in range(1, len(configs)):
        a, b = configs[k - 1], configs[k]
        m = max(1, math.ceil(float(np.abs(b - a).max()) / step - 1e-9))
        for j in range(1, m + 1):
            visit(a + (b - a) * (j / m), [k - 1, j / m])
    overall = min(mins.values())
    out = {
        "format": "supcoord-benchmark/kaiju-replay/1",
        "instance": _portable(args.instance), "angles": _portable(args.angles),
        "kaiju_version": inst["kaiju_version"],
        "replayed": replayed,
        "configurations": len(configs),
        "ang_step_deg": step,
        "robot_collision_buffer_mm": float(buf[0]),
        "buffer_override": args.buffer,
        "max_displacement_mm": float(rg.maxDisplacement),
        "poses": poses, "poses_flagged": flagged,
        "robots_flagged": len(flagged_robots),
        "robots_flagged_ids": sorted(order[i] for i in flagged_robots),
        "robots_flagged_by_kind": kinds,
        "first_flagged": first_flag,
        "min_clearance_mm": overall,
        "min_clearance_by_kind_mm": {k: (v if math.isfinite(v) else None) for k, v in mins.items()},
        "worst": worst,
        "verdict_note": ("kaiju isCollided per robot at every pose (robotGrid.cpp:698-712); robot pairs are "
                         "flagged below clearance max_displacement_mm, fiducials/GFAs below 0, and "
                         "fiducialWatch robots in their forbidden wedge"),
        "clearance_note": ("min over poses of (distance between kaiju's collisionSegWokXYZ segments, or "
                           "fiducial point to segment, or GFA segment to segment) minus both buffers; "
                           "computed here with numpy from kaiju's own segment endpoints since kaiju does not "
                           "expose minCollideDist to Python"),
        "seconds": time.perf_counter() - t0,
    }
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
    print(json.dumps({k: out[k] for k in ("poses", "poses_flagged", "robots_flagged", "min_clearance_mm",
                                          "seconds")}))


# --------------------------------------------------------------------------- main


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--wokcalib", help="directory with the APO positionerTable/wokCoords/fiducialCoords "
                    "CSVs (default: links to ../shared/instruments/sdss-v beside the checkout)")
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("instances", help="kaiju grids with kaiju's random decollided targets")
    p.add_argument("--out", required=True)
    p.add_argument("--seeds", type=int, default=10)
    p.add_argument("--grids", default="hex61,hex127,hex547,apo,lco")
    p = sub.add_parser("plan", help="run kaiju's planner on an instance")
    p.add_argument("--instance", required=True)
    p.add_argument("--planner", choices=["greedy", "mdp", "mdp1"], default="greedy",
                   help="greedy = pathGenGreedy; mdp = pathGenMDP2 (jaeger's 'mdp'); mdp1 = pathGenMDP")
    p.add_argument("--direction", choices=["fold", "unfold", "direct"], default="fold")
    p.add_argument("--greed", type=float, default=GREED)
    p.add_argument("--phobia", type=float, default=PHOBIA)
    p.add_argument("--plan-seed", type=int, default=None, help="RobotGrid seed (default: the instance's kaiju_seed)")
    p.add_argument("--no-smooth", action="store_true",
                   help="skip getPathPair (no path_smoothed; it is always skipped when kaiju failed, as in jaeger)")
    p.add_argument("--out", required=True)
    p = sub.add_parser("field", help="an instance from a supcoord PROBLEM.json on the wok (targets, offline)")
    p.add_argument("--problem", required=True)
    p.add_argument("--seed", type=int, default=0, help="benchmark seed (kaiju seed = seed + 1)")
    p.add_argument("--out", required=True)
    p = sub.add_parser("jaeger", help="jaeger's decollision and deadlock resolution over kaiju's planner")
    p.add_argument("--instance", required=True)
    p.add_argument("--planner", choices=["greedy", "mdp"], default="mdp", help="jaeger's default: mdp")
    p.add_argument("--direction", choices=["fold", "direct"], default="fold")
    p.add_argument("--retries", type=int, default=5, help="jaeger's n_deadlock_retries (default 5)")
    p.add_argument("--force", action="store_true", help="jaeger's force=True: go on after the retries")
    p.add_argument("--seed", type=int, default=None, help="grid seeds (default: the instance's kaiju_seed)")
    p.add_argument("--choice-seed", type=int, default=0, help="seed of numpy.random.choice")
    p.add_argument("--max-wall", type=float, default=None,
                   help="start no new plan after this many seconds (a benchmark limit; the outcome says so)")
    p.add_argument("--out", required=True)
    p = sub.add_parser("replay", help="kaiju's collision verdict along an angle plan")
    p.add_argument("--instance", required=True)
    p.add_argument("--angles", required=True)
    p.add_argument("--buffer", type=float, default=None, help="robot collision buffer override (mm)")
    p.add_argument("--ang-step", type=float, default=None, help="interpolation step (default kaiju's)")
    p.add_argument("--steps", action="store_true",
                   help="replay angles_deg step by step even when the plan has timed trajectories")
    p.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    _kaiju(args.wokcalib)
    {"instances": cmd_instances, "plan": cmd_plan, "replay": cmd_replay, "field": cmd_field,
     "jaeger": cmd_jaeger}[args.cmd](args)


if __name__ == "__main__":
    main()
