"""Cross-check ``supcoord.instruments`` against kaiju itself (SDSS-V's planner).

Builds kaiju's ``RobotGridAPO``/``RobotGridLCO`` from the calibration tables supcoord ships
(through coordio's ``$WOKCALIB_DIR``), then compares, for every robot at many joint angles:
the beta collision segment (``collisionSegWokXYZ``) with :func:`robot_forward`, the three
fibres (``metWokXYZ``/``apWokXYZ``/``bossWokXYZ``) with :func:`fibre_xy`, the alpha-axis
position (coordio ``tangentToWok`` of the tangent origin, as kaiju's own plots compute it)
with ``bases``, kaiju's inverse kinematics with :func:`fibre_joints`, every fiducial and GFA
(position, segment, buffer), the buffers, handedness and fiducial-watch flags, and finally
kaiju's per-robot collision verdicts on random grid states with a verdict computed from
supcoord's geometry alone.

Needs kaiju (not a supcoord dependency); run it with a Python that has it::

    python3 -m venv kaiju-venv && ../shared/tools/install-kaiju.sh kaiju-venv/bin/python
    kaiju-venv/bin/python benchmarks/kaiju_geometry_check.py [--states 20] [--seed 1] [--ang-step 0.1]

supcoord itself is imported from this checkout's ``src`` (it needs only numpy here).
Exit status 1 if any difference exceeds ``--tol`` mm (1e-9) or any verdict differs.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from supcoord.instruments import (
    fibre_joints,
    fibre_xy,
    load_instrument,
    robot_collision_distance,
    robot_forward,
)
from supcoord.instruments.sdss_v import FIDUCIAL_WATCH

TABLES = ("positionerTable", "wokCoords", "fiducialCoords", "gfaCoords")


def _calib_dirs(root: Path) -> str:
    """coordio wants one directory per site with unprefixed file names."""
    from importlib import resources

    data = resources.files("supcoord.instruments").joinpath("data", "sdss_v")
    dirs = []
    for site in ("apo", "lco"):
        d = root / site
        d.mkdir()
        for t in TABLES:
            with data.joinpath(f"{site}_{t}.csv").open("rb") as src, open(d / f"{t}.csv", "wb") as dst:
                shutil.copyfileobj(src, dst)
        dirs.append(str(d))
    return ":".join(dirs)


def seg_dist(p0, p1, q0, q1):
    """Distance between segments p0p1 and q0q1 (2-D arrays of shape (..., 2)), vectorised."""
    def point_seg(x, a, b):
        ab = b - a
        den = (ab * ab).sum(-1)
        t = np.where(den > 0, ((x - a) * ab).sum(-1) / np.where(den > 0, den, 1), 0.0)
        t = np.clip(t, 0, 1)[..., None]
        return np.linalg.norm(x - (a + t * ab), axis=-1)

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    d1, d2 = p1 - p0, q1 - q0
    r = q0 - p0
    den = cross(d1, d2)
    ok = np.abs(den) > 1e-15
    s = np.where(ok, cross(r, d2) / np.where(ok, den, 1), -1)
    u = np.where(ok, cross(r, d1) / np.where(ok, den, 1), -1)
    inter = ok & (s >= 0) & (s <= 1) & (u >= 0) & (u <= 1)
    m = np.minimum(np.minimum(point_seg(p0, q0, q1), point_seg(p1, q0, q1)),
                   np.minimum(point_seg(q0, p0, p1), point_seg(q1, p0, p1)))
    return np.where(inter, 0.0, m)


def check_site(name: str, grid_cls, states: int, seed: int, tol: float, ang_step: float) -> bool:
    import coordio.libcoordio as lc

    geom = load_instrument(name)
    grid = grid_cls(stepSize=ang_step)      # kaiju's default stepSize is 0.1; scaleFac 1
    rng = np.random.default_rng(seed)
    by_id = grid.robotDict
    index = {pid: k for k, pid in enumerate(geom.positioner_ids)}
    ok = True

    def report(what, value, limit=tol):
        nonlocal ok
        flag = "ok" if value <= limit else "FAIL"
        ok &= value <= limit
        print(f"  {what:<58} {value:.3e}  {flag}")

    print(f"{name}: kaiju {len(by_id)} robots, {len(grid.fiducialDict)} fiducials, {len(grid.gfaDict)} GFAs; "
          f"supcoord {len(geom.hole_ids)} robots, {geom.obstacle_kinds.count('fiducial')} fiducials, "
          f"{geom.obstacle_kinds.count('gfa')} GFAs")
    ok &= set(by_id) == set(geom.positioner_ids)
    holes = max(float(by_id[pid].holeID != geom.hole_ids[k]) for pid, k in index.items())
    report("holeID mismatches (robots)", holes, 0)
    hole_xy = np.array([by_id[pid].basePos[:2] for pid in geom.positioner_ids])
    report("kaiju basePos (xPos, yPos) vs hole_xy (mm)", np.abs(hole_xy - geom.hole_xy).max())
    axis = np.array([lc.tangentToWok([0.0, 0.0, 0.0], r.basePos, r.iHat, r.jHat, r.kHat, r.elementHeight,
                                     r.scaleFac, r.dxyz[0], r.dxyz[1], r.dxyz[2])[:2]
                     for r in (by_id[pid] for pid in geom.positioner_ids)])
    report("alpha axis (tangentToWok of origin, dx/dy applied) vs bases", np.abs(axis - geom.bases).max())
    report("alpha offsets vs table", max(abs(by_id[p].alphaOffDeg - geom.alpha_offset_deg[k])
                                         for p, k in index.items()))
    report("beta offsets vs table", max(abs(by_id[p].betaOffDeg - geom.beta_offset_deg[k]) for p, k in index.items()))
    buffers = {r.collisionBuffer for r in by_id.values()}
    report(f"robot collisionBuffer {sorted(buffers)} vs {geom.robot_buffer}",
           max(abs(b - geom.robot_buffer) for b in buffers))
    report("robots lefthanded (count; supcoord: right-handed)", sum(r.lefthanded for r in by_id.values()), 0)
    watch = np.array([by_id[p].fiducialWatch for p in geom.positioner_ids])
    report(f"fiducialWatch flags differing ({int(watch.sum())} flagged)",
           float((watch != geom.fiducial_watch).sum()), 0)
    apogee = np.array([by_id[p].hasApogee for p in geom.positioner_ids])
    report("hasApogee flags differing", float((apogee != geom.has_apogee).sum()), 0)

    # fixed angles plus random ones, every robot
    angles = [(0, 0), (0, 180), (10, 170), (90, 90), (359.9, 0.1)] + \
        [tuple(x) for x in np.column_stack([rng.uniform(0, 360, 8), rng.uniform(0, 360, 8)])]
    err = {"segment": 0.0, "metrology": 0.0, "apogee": 0.0, "boss": 0.0, "z": 0.0}
    attr = {"metrology": "metWokXYZ", "apogee": "apWokXYZ", "boss": "bossWokXYZ"}
    for a, b in angles:
        ours = robot_forward(geom, np.arange(len(geom.hole_ids)), a, b)
        fib = {f: fibre_xy(geom, np.arange(len(geom.hole_ids)), a, b, f) for f in attr}
        for k, pid in enumerate(geom.positioner_ids):
            r = by_id[pid]
            r.setAlphaBeta(float(a), float(b))
            seg = np.array(r.collisionSegWokXYZ)
            err["segment"] = max(err["segment"], np.abs(seg[:, :2] - ours[k]).max())
            err["z"] = max(err["z"], np.abs(seg[:, 2] - 143.1).max())
            for f, at in attr.items():
                err[f] = max(err[f], np.abs(np.array(getattr(r, at))[:2] - fib[f][k]).max())
    for f, e in err.items():
        what = "beta collision segment (collisionSegWokXYZ)" if f == "segment" else \
            "segment z - 143.1 (all segments in one plane)" if f == "z" else f"{f} fibre ({attr[f]})"
        report(f"{what}, {len(angles)} angle pairs x {len(geom.hole_ids)}", e)

    # inverse kinematics (kaiju alphaBetaFromWokXYZ) on reachable points
    from kaiju.cKaiju import ApogeeFiber, BossFiber, MetrologyFiber
    ftype = {"metrology": MetrologyFiber, "apogee": ApogeeFiber, "boss": BossFiber}
    worst = 0.0
    for k, pid in enumerate(geom.positioner_ids[:100]):
        for f, kind in ftype.items():
            xy = fibre_xy(geom, k, rng.uniform(0, 360), rng.uniform(5, 175), f)
            ours = fibre_joints(geom, k, xy, f)
            theirs = by_id[pid].alphaBetaFromWokXYZ([xy[0], xy[1], 143.1], kind)
            worst = max(worst, np.abs(np.array(theirs) - ours).max())
    report("fibre_joints vs alphaBetaFromWokXYZ (deg), 100 robots x 3 fibres", worst, 1e-6)

    # obstacles
    fid = {f"F{f.id}": f for f in grid.fiducialDict.values()}
    fk = [i for i, kind in enumerate(geom.obstacle_kinds) if kind == "fiducial"]
    fe = max(np.abs(np.array(fid[geom.obstacle_ids[i]].xyzWok[:2]) - geom.obstacles[i, 0]).max() for i in fk)
    report("fiducial positions (xyzWok) vs obstacles", fe)
    report("fiducial buffers", max(abs(fid[geom.obstacle_ids[i]].collisionBuffer - geom.obstacle_buffers[i])
                                   for i in fk))
    gk = [i for i, kind in enumerate(geom.obstacle_kinds) if kind == "gfa"]
    gfas = [grid.gfaDict[j] for j in sorted(grid.gfaDict)]
    report("GFA segments (collisionSegWokXYZ) vs obstacles",
           max(np.abs(np.array(g.collisionSegWokXYZ)[:, :2] - geom.obstacles[i]).max() for g, i in zip(gfas, gk)))
    report("GFA buffers", max(abs(g.collisionBuffer - geom.obstacle_buffers[i]) for g, i in zip(gfas, gk)))
    report(f"maxDisplacement at {ang_step:g} deg ({grid.maxDisplacement:.6f}) vs supcoord",
           abs(grid.maxDisplacement - (robot_collision_distance(geom, ang_step) - 2 * geom.robot_buffer)))

    # collision verdicts on random grid states (alpha, beta anywhere in kaiju's [0, 360], or beta near folded)
    n = len(geom.hole_ids)
    far = np.linalg.norm(geom.bases[:, None] - geom.bases[None], axis=-1) < 2 * (7.6 + 14.8 + 2) + 1
    np.fill_diagonal(far, False)
    ii, jj = np.nonzero(np.triu(far))
    thresh = robot_collision_distance(geom, grid.angStep)
    disagree = collided = 0
    for state in range(states):       # odd states: betas near folded, few collisions, more near misses
        a, b = rng.uniform(0, 360, n), rng.uniform(0, 360, n) if state % 2 == 0 else rng.uniform(130, 180, n)
        for k, pid in enumerate(geom.positioner_ids):
            by_id[pid].setAlphaBeta(float(a[k]), float(b[k]))
        seg = robot_forward(geom, np.arange(n), a, b)
        hit = np.zeros(n, bool)
        close = seg_dist(seg[ii, 0], seg[ii, 1], seg[jj, 0], seg[jj, 1]) < thresh
        hit[ii[close]] = hit[jj[close]] = True
        obs = geom.obstacles
        d = seg_dist(seg[:, None, 0], seg[:, None, 1], obs[None, :, 0], obs[None, :, 1])
        hit |= (d < geom.robot_buffer + geom.obstacle_buffers[None]).any(1)
        hit |= geom.fiducial_watch & (b < FIDUCIAL_WATCH[0] + FIDUCIAL_WATCH[1] * a)
        kaiju_hit = np.array([grid.isCollided(pid) for pid in geom.positioner_ids])
        disagree += int((hit != kaiju_hit).sum())
        collided += int(kaiju_hit.sum())
    report(f"collision verdicts differing ({states} random states, {collided} collided robot-states)",
           float(disagree), 0)
    return ok


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--states", type=int, default=20, help="random grid states for the verdict check")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--ang-step", type=float, default=0.1, help="kaiju stepSize (deg): sets its collision margin")
    ap.add_argument("--tol", type=float, default=1e-9, help="largest accepted difference (mm)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["WOKCALIB_DIR"] = _calib_dirs(Path(tmp))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")      # coordio: no focal-plane model etc. (not needed here)
            import kaiju
            from kaiju.robotGrid import RobotGridAPO, RobotGridLCO
        print(f"kaiju {getattr(kaiju, '__version__', '?')} from {Path(kaiju.__file__).parent}")
        ok = check_site("sdss-v-apo", RobotGridAPO, args.states, args.seed, args.tol, args.ang_step)
        ok &= check_site("sdss-v-lco", RobotGridLCO, args.states, args.seed + 1, args.tol, args.ang_step)
    print("all checks passed" if ok else "SOME CHECKS FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
