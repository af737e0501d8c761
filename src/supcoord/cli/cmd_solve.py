"""``supcoord solve PROBLEM.json [--out PLAN.json] [--figure FILE] [--json]``: plan a problem.

Prints the PLAN.json object (``docs/formats.md``): ``complete`` with a validated plan,
``partial`` where no plan puts every robot on its target (the most robots on target, the
others named with a reason; exit 0; ``--require-all``: ``infeasible`` instead),
``infeasible`` with a ``reason`` naming the positioners (exit 0: an answer), or — when
``--max-nodes``/``--timeout`` run out — ``unknown`` with the statistics so far (exit 3).
A missing or malformed problem, or a target that itself collides, exits 2; a start whose
robots collide with each other is repaired first (:mod:`supcoord.planning.start_repair`,
PLAN.json ``repair``; with ``--speed``, timed too: its moves one after another, then the plan's),
which the output says in one line.  ``--keep 3,17`` keeps robots at
their start as obstacles (:mod:`supcoord.problems.fixed_robots`).
``--figure``: ``.gif`` animates a complete plan, ``.png``/``.pdf``/``.svg``/``.jpg`` draw
a strip of its frames; an infeasible answer draws the problem with the positioners
of its certificate in orange.  Fields of the problem file that the format does not
know are reported as warnings on standard error.  A complete plan carries its joint
angles (``angles_deg``); ``--speed DEG_PER_S`` adds timed ``trajectories`` and
``motion_time_s`` (:mod:`supcoord.problems.trajectory`: the timing model), and
``--trajectories-csv FILE.csv`` writes the trajectories as ``robot,joint,t_s,deg`` rows.
"""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path
from typing import Iterator, Sequence

from .common import CommandResult, Console, add_problem_argument, budget_from_args

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run", "figure_suffix", "writable", "FIGURE_SUFFIXES"]

#: what ``--figure`` accepts (the same list as ``supcoord.figures.problem_figures.FIGURE_SUFFIXES``,
#: repeated here so that a bad name is refused before matplotlib is imported)
FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".gif")

EXAMPLE = """examples:
  supcoord solve problem.json --out plan.json --figure plan.gif
  supcoord solve problem.json --json --timeout 60
  -> {"status": "complete", "configurations": [...], "makespan": 9, "lower_bound": 6, ...}
  supcoord solve problem.json --route monolithic     # the plain whole-grid method
  supcoord solve problem.json --out plan.json --speed 30 --trajectories-csv traj.csv
  supcoord solve apo.json --jaeger paths.json --jaeger-reverse back.json --rpm 2"""


HELP = "plan collision-free moves from start to target (or prove none exists)"
DESCRIPTION = ("Solve a geometric coordination problem symbolically: a validated plan, "
              "or 'infeasible' with the positioners involved.")
BUDGETS = True  # --max-nodes/--timeout/--backend


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord solve``'s own options (:func:`.main.build_parser` adds the common ones)."""
    add_problem_argument(p)
    p.add_argument("--out", metavar="PLAN.json", help="write the plan here")
    p.add_argument("--figure", metavar="FILE",
                   help="draw the answer: .gif animates the plan, .png/.pdf/.svg/.jpg a strip of frames "
                        "(infeasible: the positioners involved)")
    p.add_argument("--route", choices=["local", "monolithic"], default="local",
                   help="local: exact windows with certificates (default); monolithic: one model of the whole grid")
    p.add_argument("--order", choices=["rcm", "hex"], help="variable order (default: rcm for local, hex for monolithic)")
    p.add_argument("--speed", type=float, metavar="DEG_PER_S",
                   help="joint speed in degrees per second (1e-3 to 1e5): the plan gets timed trajectories and "
                        "motion_time_s (each robot at its own pace; a neighbour waits only where their motions can meet)")
    p.add_argument("--trajectories-csv", metavar="FILE.csv",
                   help="write the trajectories as robot,joint,t_s,deg rows (needs --speed)")
    p.add_argument("--jaeger", metavar="PATHS.json",
                   help="write the plan as SDSS-V's robot controller jaeger's trajectory (to the targets): "
                        "{positioner_id: {alpha: [[deg, s], ...], beta: [...]}}")
    p.add_argument("--jaeger-reverse", metavar="BACK.json", help="write jaeger's trajectory back to the starts")
    p.add_argument("--rpm", type=float, help="joint speed of the jaeger trajectories in RPM (default the "
                                             "instrument's: SDSS-V 2, at most 3)")
    p.add_argument("--acceleration", type=float, metavar="DEG_PER_S2",
                   help="joint acceleration limit of the jaeger trajectories (default: none)")
    p.add_argument("--start-delay", type=float, metavar="S",
                   help="seconds before the jaeger trajectories' first motion (default the instrument's: SDSS-V 1)")
    p.add_argument("--single-move-only", action="store_true",
                   help="answer infeasible as soon as no plan moves one joint at a time (default: then search "
                        "plans with several joints and positioners moving at once before answering)")
    p.add_argument("--no-refine", action="store_true",
                   help="answer with the lattice's single-move certificate (default: on problems too large for the "
                        "simultaneous search, solve once more on a lattice with steps 2/3 as long)")
    p.add_argument("--keep", metavar="ROBOTS",
                   help="robots (indices from 0, comma-separated: 3,17) kept at their start as obstacles for the others")
    p.add_argument("--require-all", action="store_true",
                   help="answer complete or infeasible only (default: where no plan puts every robot on its target, "
                        "a partial plan with the most robots on target, the others named with a reason)")
    p.add_argument("--off-target-end", choices=["start", "folded"], default="start",
                   help="where a partial plan's robots off target end: start (default), or folded (beta at 180 deg, "
                        "alpha where it starts) where a plan reaches it")
    p.add_argument("--improve", type=int, metavar="N",
                   help="space-time re-plannings that may shorten the plan (0: off; default: 4 per positioner, "
                        "at least 200); work, not seconds, so the same input gives the same plan anywhere")


def figure_suffix(path: str | None, inputs: Sequence[str] = ()) -> str | None:
    """The ``--figure`` file's suffix, refused (exit 2) before any work unless it is one of
    :data:`FIGURE_SUFFIXES` and a file supcoord may write (:func:`writable`)."""
    from ..errors import InputError

    if path is None:
        return None
    suffix = Path(path).suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        raise InputError(f"--figure must end in {', '.join(FIGURE_SUFFIXES)}, got {path!r}", value=path)
    writable(path, "--figure", inputs)
    return suffix


def writable(path: str | None, flag: str, inputs: Sequence[str] = ()) -> None:
    """Refuse (exit 2), before any work is done, an output path that is one of the
    ``inputs``, a link, a directory, FIFO or device, or in a missing or read-only
    directory (:func:`supcoord.outputs.check_output`)."""
    from ..outputs import check_output

    if path is not None:
        check_output(path, inputs, what=flag)


@contextlib.contextmanager
def as_option(flag: str) -> Iterator[None]:
    """A write failure the library reports for its ``output`` (a full disk, a read-only
    folder) is reported for the option that named the file."""
    from ..errors import InputError

    try:
        yield
    except InputError as exc:
        if not exc.message.startswith("output: "):
            raise
        raise InputError(flag + exc.message[6:], value=exc.value, where=exc.where) from None


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    """``supcoord solve``: check the outputs before the work, solve, write, and say what was done."""
    from ..planning.planner import FinerLattice, Simultaneous
    from ..planning.routes import route_named
    from ..planning.start_repair import solve_any_start
    from ..problems.fixed_robots import keep_fixed, parse_robot_list
    from ..problems.repair_phase import load_problem_any_start, start_collisions

    budget = budget_from_args(args)
    speed, improve, csv, jaeger = _checked_options(args)
    console.progress("load", {"file": args.problem})
    problem = load_problem_any_start(args.problem)
    for warning in problem.warnings:
        console.warn(warning)
    if getattr(args, "keep", None) is not None:
        problem = keep_fixed(problem, parse_robot_list(args.keep, problem.n, "--keep"), "--keep")
    colliding = start_collisions(problem)
    if colliding and any(jaeger.values()):
        from ..errors import InputError

        n_pairs = f"{len(colliding)} pair" + ("s" if len(colliding) > 1 else "")
        raise InputError(f"the start collides (robots {colliding[0][0]} and {colliding[0][1]}, {n_pairs}): "
                         f"jaeger's trajectory of its repair phase is not written (--speed times it)", value=None,
                         where="--jaeger" if jaeger["--jaeger"] else "--jaeger-reverse")
    if any(jaeger.values()):  # the limits refused before the work
        _check_jaeger_limits(problem, args)
    plan = solve_any_start(problem, route=route_named(args.route, args.order), backend=args.backend, budget=budget,
                 progress=console.progress, speed=speed, improve=improve,
                 simultaneous=None if args.single_move_only else Simultaneous(),
                 finer=None if args.no_refine else FinerLattice(),
                 when_incomplete="infeasible" if args.require_all else "partial",
                 off_target_end=getattr(args, "off_target_end", "start"))
    if args.out:
        with as_option("--out"):
            plan.dump(args.out, problem)
    if csv is not None and plan.trajectories is not None:
        from ..outputs import atomic_write_text
        from ..problems.trajectory import trajectories_csv

        atomic_write_text(csv, trajectories_csv(plan.trajectories), what="--trajectories-csv")
    exported = _write_jaeger(problem, plan, args, jaeger)
    if args.figure:
        from ..figures.plan_figures import save_plan_figure

        with as_option("--figure"):
            save_plan_figure(problem, plan, args.figure, progress=console.progress)
    text = _summary(problem, plan, speed)
    if colliding:
        text = _repair_line(colliding, plan) + "\n" + text
    if args.out:
        text += f"\nplan written to {args.out}"
    if csv is not None:
        text += (f"\ntrajectories written to {csv}" if plan.trajectories is not None
                 else f"\nno trajectories (the plan is {plan.status}): {csv} not written")
    text += exported
    if args.figure:
        text += f"\nfigure written to {args.figure}"
    # docs/formats.md: "unknown" (a budget ran out) exits 3, also when the planner returns it as a plan
    return CommandResult(payload=plan.to_json(problem), text=text, exit_code=3 if plan.status == "unknown" else 0)


def _checked_options(args: argparse.Namespace) -> tuple[float | None, int | None, str | None, dict[str, str | None]]:
    """``--speed``, ``--improve``, ``--trajectories-csv`` and the jaeger files, refused (exit 2)
    before any work; every output file checked (:func:`writable`) and none named twice."""
    from ..errors import InputError
    from ..problems.trajectory import check_speed

    speed = check_speed(getattr(args, "speed", None), "--speed")
    improve = getattr(args, "improve", None)
    if improve is not None and not 0 <= improve <= 10**7:
        raise InputError(f"must be a number of re-plannings in [0, 10000000], got {improve}", value=improve,
                         where="--improve")
    csv = getattr(args, "trajectories_csv", None)
    figure_suffix(args.figure, [args.problem])
    writable(args.out, "--out", [args.problem])
    if csv is not None:
        if speed is None:
            raise InputError("needs --speed (the trajectories' joint speed)", value=csv, where="--trajectories-csv")
        if Path(csv).suffix.lower() != ".csv":
            raise InputError(f"must end in .csv, got {csv!r}", value=csv, where="--trajectories-csv")
        writable(csv, "--trajectories-csv", [args.problem])
    jaeger = {flag: getattr(args, name, None) for flag, name in (("--jaeger", "jaeger"),
                                                                 ("--jaeger-reverse", "jaeger_reverse"))}
    for flag, f in jaeger.items():
        writable(f, flag, [args.problem])
    outputs = [(flag, Path(f).absolute()) for flag, f in (("--out", args.out), ("--figure", args.figure),
                                                           ("--trajectories-csv", csv), *jaeger.items()) if f]
    for i, (flag, path) in enumerate(outputs):
        for other, there in outputs[i + 1:]:
            if path == there:
                raise InputError(f"{flag} and {other} name the same file", value=str(path), where=flag)
    return speed, improve, csv, jaeger


def _check_jaeger_limits(problem, args: argparse.Namespace) -> None:
    """The jaeger trajectories' limits refused before the work, named by their flags."""
    from ..errors import InputError
    from ..problems.jaeger import jaeger_limits

    try:
        jaeger_limits(problem, args.rpm, args.acceleration, args.start_delay)
    except InputError as exc:
        flag = {"rpm": "--rpm", "acceleration": "--acceleration", "start_delay_s": "--start-delay"}
        raise InputError(exc.message, value=exc.value, where=flag.get(str(exc.where), exc.where)) from None


def _summary(problem, plan, speed: float | None) -> str:
    """The answer in words: the plan's size and work, or the verdict and its reason."""
    if plan.status == "partial":
        parked = plan.stats.get("partial", {}).get("parked", [])
        return (f"PARTIAL: {plan.reason}\n"
                + ("".join(f"parked off target: robot {p['robot']} at lattice position "
                           f"({', '.join(map(str, p['at']))}), freeing the target of robot"
                           f"{'s' if len(p['freed']) > 1 else ''} {', '.join(map(str, p['freed']))}\n"
                           for p in parked))
                + ("optimal: no plan of the discretised model leaves less off target"
                   if plan.optimal and plan.on_target == plan.on_target_bound else
                   f"optimal among plans whose robots off target end at their starts; at most "
                   f"{plan.on_target_bound} robots could be on target" if plan.optimal else
                   f"not proven optimal: at most {plan.on_target_bound} robots could be on target")
                + f"; makespan {plan.makespan}, {plan.stats.get('seconds', 0):.2f} s")
    if plan.status != "complete":
        return f"{plan.status.upper()}: {plan.reason}"
    s = plan.stats
    text = (f"COMPLETE: {problem.n} positioners, makespan {plan.makespan} (lower bound {plan.lower_bound}), "
            + (f"{s.get('single_moves')} single moves, " if s.get("plan_model") != "simultaneous" else
               "simultaneous moves (no single-move plan exists), ")
            + f"{s.get('windows')} symbolic solve(s), "
            f"{s.get('seconds', 0):.2f} s, peak {s.get('bdd_nodes')} BDD nodes")
    if plan.lattice is not None:
        text += (f"\nplanned on the finer {' × '.join(map(str, plan.lattice))} lattice (the problem's has only a "
                 f"single-move certificate, positioners {', '.join(map(str, s['refined']['certificate']))})")
    if plan.motion_time_s is not None:
        text += f"\nmotion time {plan.motion_time_s:.3f} s at {speed:g} deg/s"
    return text


def _repair_line(colliding: list, plan) -> str:
    """One line: the start collides, and what the repair moved (PLAN.json ``repair``)."""
    pairs = f"{len(colliding)} pair" + ("s" if len(colliding) > 1 else "")
    text = f"the start collides ({pairs}, first robots {colliding[0][0]} and {colliding[0][1]})"
    repair = plan.repair.to_json() if plan.repair is not None else plan.stats.get("repair")
    if repair is None:
        return text + ": not repaired"
    how = ("the fewest any repair moves" if repair["minimum"]
           else f"at least {repair['lower_bound']} must move")
    timed = plan.stats.get("repair_motion_s")
    return (text + f": repaired first by moving robots {', '.join(map(str, repair['moved']))} in {repair['steps']} "
            f"steps ({how})" + (f", the first {timed:.3f} s of the motion" if timed is not None else ""))


def _write_jaeger(problem, plan, args: argparse.Namespace, files: dict) -> str:
    """Write ``--jaeger``/``--jaeger-reverse`` for a complete or partial plan; the lines saying so
    (for a partial plan, the robots off target: PLAN.json's ``off_target``)."""
    from ..problems.jaeger import jaeger_paths, positioner_keys, write_jaeger

    text = ""
    for flag, path in files.items():
        if path is None:
            continue
        if plan.status not in ("complete", "partial"):
            text += f"\nno jaeger trajectory (the plan is {plan.status}): {path} not written"
            continue
        paths = jaeger_paths(problem, plan, rpm=args.rpm, acceleration=args.acceleration,
                             start_delay_s=args.start_delay, reverse=flag == "--jaeger-reverse")
        write_jaeger(path, paths, (args.problem,))
        text += (f"\njaeger trajectory {'back to the starts' if flag == '--jaeger-reverse' else 'to the targets'} "
                 f"written to {path} ({paths.points} points, {paths.motion_time_s:.3f} s at "
                 f"{paths.speed_deg_s:g} deg/s)")
        if plan.status == "partial":
            keys, folded = positioner_keys(problem), sum(e.end == "folded" for e in plan.off_target)
            parked = sum(e.end == "parked" for e in plan.off_target)
            text += (f"; {len(plan.off_target)} robots off target stay at their starts"
                     + (f" or fold ({folded} folded)" if folded else "")
                     + (f" or park ({parked} parked)" if parked else "")
                     + f" (positioner IDs {', '.join(keys[e.robot] for e in plan.off_target)}; PLAN.json off_target)")
    return text
