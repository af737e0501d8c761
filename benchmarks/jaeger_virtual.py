#!/usr/bin/env python
"""Send a supcoord jaeger export through jaeger's own trajectory code to jaeger's virtual robots.

Needs SDSS-V's robot controller jaeger (PyPI ``jaeger``) importable next to supcoord::

    python benchmarks/jaeger_virtual.py PROBLEM.json PATHS.json [--reverse] [--out RESULT.json]

What runs (jaeger's code, unchanged): ``jaeger.testing.VirtualFPS`` (positioners on a virtual
CAN bus) with one ``VirtualPositioner`` per key of PATHS.json, each standing at its start
angles; then ``jaeger.commands.trajectory.send_trajectory(fps, paths, use_sync_line=False)``,
which builds a ``Trajectory`` (``validate``), sends ``SEND_NEW_TRAJECTORY``, the points as
``SEND_TRAJECTORY_DATA`` (``SendTrajectoryData.calculate_positions``: motor steps and 0.5 ms
units, int32), ``TRAJECTORY_DATA_END``, then ``START_TRAJECTORY``, waits for the robots and
compares their positions with each path's last point (within 0.1 deg) — jaeger's own
"reached their destinations" check.

jaeger's virtual positioner acknowledges trajectory data but does not move (jaeger's own
``tests/test_trajectory.py::test_send_trajectory`` is marked xfail for that reason).  So the
positioners here record the bytes they receive, decode them the way the firmware reads them
(int32 motor steps, 2**30 per turn; int32 time units of 0.5 ms) and, on START_TRAJECTORY,
run that decoded trajectory in real time: after its last time they stand at its last point.
The script then checks, independently of jaeger: the decoded points are the file's (to one
motor step and one time unit), times still strictly increase after the firmware's truncation,
and every robot ends at the problem's target angles (start angles with ``--reverse``).
"""

from __future__ import annotations

import argparse
import asyncio
import importlib.metadata
import json
import os
import sys
import time

import numpy as np

STEPS_PER_TURN = 2**30   # jaeger etc/jaeger_*.yml positioner.motor_steps
TIME_STEP = 0.0005       # positioner.time_step (s)


def decode(chunks: list[bytes]) -> np.ndarray:
    """``[deg, s]`` rows from SEND_TRAJECTORY_DATA payloads (int32 steps, int32 time units, little-endian)."""
    raw = np.frombuffer(b"".join(chunks), dtype="<i4").reshape(-1, 2).astype(float)
    return np.stack([raw[:, 0] * 360.0 / STEPS_PER_TURN, raw[:, 1] * TIME_STEP], axis=1)


async def run(paths: dict, starts: dict, speedup_log: list, init_timeout: float | None = None) -> dict:
    from jaeger import config
    from jaeger.commands import CommandID
    from jaeger.commands.trajectory import send_trajectory
    from jaeger.positioner import Positioner
    from jaeger.testing import VirtualFPS, VirtualPositioner

    config["fps"]["use_lock"] = False
    config["safe_mode"] = False
    config["positioner"]["trajectory_dump_path"] = "/tmp/jaeger_virtual_dumps"
    config["fps"]["initialise_timeouts"] = max(0.5, len(paths) / 50, init_timeout or 0)  # every one answers GET_ID

    received: dict[int, dict[str, list[bytes]]] = {}

    class RunningPositioner(VirtualPositioner):
        """jaeger's virtual positioner that also runs the trajectory it was sent."""

        async def process_message(self, msg, positioner_id, command_id, uid):
            cid = CommandID(command_id)
            mine = received.setdefault(self.positioner_id, {"alpha": [], "beta": [], "n": None})
            if cid == CommandID.SEND_NEW_TRAJECTORY:
                mine.update(alpha=[], beta=[], n=(int.from_bytes(msg.data[0:4], "little"),
                                                  int.from_bytes(msg.data[4:8], "little")))
            elif cid == CommandID.SEND_TRAJECTORY_DATA:
                arm = "alpha" if len(mine["alpha"]) < mine["n"][0] else "beta"
                for i in range(0, len(msg.data), 8):
                    if len(mine[arm]) >= mine["n"][0 if arm == "alpha" else 1]:
                        arm = "beta"
                    mine[arm].append(bytes(msg.data[i:i + 8]))
            elif cid == CommandID.START_TRAJECTORY and mine["n"] is not None:
                asyncio.create_task(self._run(decode(mine["alpha"]), decode(mine["beta"])))
            await super().process_message(msg, positioner_id, command_id, uid)

        async def _run(self, alpha: np.ndarray, beta: np.ndarray) -> None:
            from jaeger.maskbits import PositionerStatus as S

            moving = S.DISPLACEMENT_COMPLETED | S.DISPLACEMENT_COMPLETED_ALPHA | S.DISPLACEMENT_COMPLETED_BETA
            self.status &= ~moving
            await asyncio.sleep(max(alpha[-1, 1], beta[-1, 1]))
            self.position = (float(alpha[-1, 0]), float(beta[-1, 0]))
            self.status |= moving

    fps = await VirtualFPS.create(initialise=False)
    fps.pid_lock = True
    for pid in paths:
        vp = RunningPositioner(pid, bus=fps._vpositioner_bus, position=tuple(starts[pid]))
        fps._vpositioners[pid] = vp
    jaeger_update_status = Positioner.update_status
    if init_timeout:  # during initialisation only: 500 virtual positioners answer in one Python process
        async def patient_update_status(self, status=None, timeout=1.0):
            return await jaeger_update_status(self, status, timeout=max(timeout, init_timeout))
        Positioner.update_status = patient_update_status
    try:
        await fps.initialise()
    finally:
        Positioner.update_status = jaeger_update_status
    missing = sorted(set(paths) - set(fps.positioners))
    if missing:
        raise RuntimeError(f"{len(missing)} virtual positioners did not answer jaeger's initialisation: {missing[:5]}")
    t0 = time.perf_counter()
    try:
        traj = await send_trajectory(fps, paths, use_sync_line=False, dump=False)
        wall = time.perf_counter() - t0
        await fps.update_position()
        ends = {pid: list(map(float, fps[pid].position)) for pid in paths}
    finally:  # as jaeger's own test fixture does
        await fps.pollers.stop()
        fps.can._command_queue_task.cancel()
    return {"entry_point": "jaeger.commands.trajectory.send_trajectory(fps, paths, use_sync_line=False, dump=False)",
            "move_time_s": traj.move_time, "data_send_time_s": traj.data_send_time, "wall_s": wall,
            "n_points": {str(k): list(v) for k, v in traj.n_points.items()}, "ends": ends,
            "received": {pid: {arm: decode(r[arm]).tolist() for arm in ("alpha", "beta")}
                         for pid, r in received.items() if r["n"] is not None}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("problem")
    ap.add_argument("paths")
    ap.add_argument("--reverse", action="store_true", help="PATHS.json runs from the targets to the starts")
    ap.add_argument("--out", help="write the result JSON here")
    ap.add_argument("--max-robots", type=int, default=None,
                    help="send only the N robots with the most points (a loaded machine's virtual bus may not "
                         "answer jaeger's initialisation for all 500 in time)")
    ap.add_argument("--init-timeout", type=float, default=None,
                    help="seconds each virtual positioner may take to answer GET_STATUS during jaeger's "
                         "initialisation (jaeger's own: 1 s; its trajectory code keeps its own timeouts)")
    args = ap.parse_args(argv)
    os.environ.setdefault("OBSERVATORY", "APO")  # jaeger reads its site's configuration on import
    from supcoord.problems.problem import load_problem
    from supcoord.problems.validate_jaeger import read_jaeger  # noqa: F401  (format check)

    problem = load_problem(args.problem)
    with open(args.paths) as f:
        data = json.load(f)
    if args.max_robots:
        busiest = sorted(data, key=lambda k: -(len(data[k]["alpha"]) + len(data[k]["beta"])))[:args.max_robots]
        data = {k: data[k] for k in busiest}
    paths = {int(k): v for k, v in data.items()}  # jaeger keys positioners by int
    from supcoord.problems.jaeger import positioner_keys

    keys = positioner_keys(problem)
    ang = problem.angles_deg(problem.start), problem.angles_deg(problem.target)
    first, last = (ang[1], ang[0]) if args.reverse else ang
    index = {int(k): p for p, k in enumerate(keys)}
    starts = {pid: first[index[pid]].tolist() for pid in paths}
    res = asyncio.run(run(paths, starts, [], args.init_timeout))
    worst_end = max(float(np.max(np.abs(np.array(res["ends"][pid]) - last[index[pid]]))) for pid in paths)
    worst_point = max_gap = 0.0
    increasing = True
    for pid, arms in res["received"].items():
        for arm in ("alpha", "beta"):
            got, want = np.array(arms[arm]), np.array(paths[pid][arm], float)
            worst_point = max(worst_point, float(np.max(np.abs(got[:, 0] - want[:, 0]))))
            max_gap = max(max_gap, float(np.max(np.abs(got[:, 1] - want[:, 1]))))
            increasing &= bool(np.all(np.diff(got[:, 1]) > 0))
    summary = {"jaeger_version": importlib.metadata.version("jaeger"), "entry_point": res["entry_point"], "robots": len(paths),
               "points": sum(len(v["alpha"]) + len(v["beta"]) for v in data.values()),
               "move_time_s": res["move_time_s"], "data_send_time_s": res["data_send_time_s"],
               "wall_s": res["wall_s"], "accepted": True, "init_timeout_s": args.init_timeout,
               "received_robots": len(res["received"]),
               "decoded_max_angle_error_deg": worst_point, "decoded_max_time_error_s": max_gap,
               "decoded_times_increase": increasing, "max_end_error_deg": worst_end,
               "at_targets": worst_end <= 360.0 / STEPS_PER_TURN * 2}
    print(json.dumps(summary, indent=1))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(summary, f, indent=1)
    return 0 if summary["at_targets"] and summary["decoded_times_increase"] else 1


if __name__ == "__main__":
    sys.exit(main())
