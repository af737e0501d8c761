"""Mutation testing of the exact core: does the test suite catch each deliberate bug?

Each mutation replaces one exact piece of source text (it must occur exactly once) in a
copy of ``src/``, then runs the test files that guard that code against the copy
(``PYTHONPATH`` first, so the copy is what the tests import). A mutation is *caught*
when some test fails; the table records which one and how long it took.

    python benchmarks/mutations.py                  # every mutation, writes results/mutations.md
    python benchmarks/mutations.py --only sweep     # the mutations whose id contains 'sweep' (or of area 'sweep')
    python benchmarks/mutations.py --only wrap,gen-range   # several, separated by commas
    python benchmarks/mutations.py --list           # what would run
    python benchmarks/mutations.py --head           # mutate the committed source, not the working tree
    python benchmarks/mutations.py --only timing --out /tmp/m.md   # write the table elsewhere

Results: ``benchmarks/results/mutations.md`` (command, date, machine, load, code version);
docs/testing.md quotes the table.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "mutations.md"
HEAD_ONLY = False


@dataclass(frozen=True)
class Mutation:
    id: str
    area: str
    path: str  # relative to src/supcoord
    old: str
    new: str
    tests: tuple[str, ...]
    what: str


MUTATIONS = [
    Mutation("supcon-no-controllability", "supcon", "synthesis/supcon.py",
             "z = zold & ~coreachable(P, bad, within=universe, method=method, events=unc)", "z = zold",
             ("tests/synthesis/test_supcon.py",), "the controllability step (remove UPre*(¬Z)) is skipped"),
    Mutation("supcon-no-nonblocking", "supcon", "synthesis/supcon.py",
             "zold = coreachable(P, P.marked & z, within=inside, method=method)", "zold = z",
             ("tests/synthesis/test_supcon.py",), "the nonblocking step (Z ∩ CoReach_Z(Qm)) is skipped"),
    Mutation("supcon-no-b0", "supcon", "synthesis/supcon.py",
             "z = universe & ~uncontrollable_blocked(G, P)", "z = universe",
             ("tests/synthesis/test_supcon.py",), "states where the spec blocks an uncontrollable event are kept"),
    Mutation("force-or", "forcibility", "synthesis/forcibility.py",
             "return Q & some_c & all_u_ok", "return Q & (some_c | all_u_ok)",
             ("tests/synthesis/test_forcibility.py",), "standard forcing: one controllable OR all uncontrollable"),
    Mutation("force-preemptive-env", "forcibility", "synthesis/forcibility.py",
             "return (env_states & all_u_ok) | (Q & ~env_states & some_c)",
             "return (env_states & all_u_ok) | (Q & some_c)",
             ("tests/synthesis/test_forcibility.py",), "preemptive forcing ignores pending uncontrollable events"),
    Mutation("witness-highest-rank", "witness", "synthesis/witness.py",
             "e, q, k = min(forced, key=lambda s: (s[2], event_key(s[0])))",
             "e, q, k = max(forced, key=lambda s: (s[2], event_key(s[0])))",
             ("tests/synthesis/test_witness.py",), "the controller forces the successor of highest rank"),
    Mutation("sweep-no-closed-form", "tables", "geometry/pair_tables.py",
             "res[ii, jj] = turn_collides(mk, bm, pm[valid][ii], joint, delta, sk, bs, ps[jj], bsum)",
             "res[ii, jj] = False",
             ("tests/geometry/test_sweep.py", "tests/geometry/test_collision.py"), "swept entries the end points leave open are free"),
    Mutation("sweep-unsound-prefilter", "tables", "geometry/pair_tables.py",
             "        length = float(mk.sweep_length(d))", "        length = 0.0",
             ("tests/geometry/test_sweep.py", "tests/geometry/test_collision.py"), "the end-point prefilter forgets the sweep length"),
    Mutation("sweep-no-reverse-arcs", "tables", "geometry/sweep.py",
             "    return np.minimum(best, arc_segment_distance(c, b, -angle, p, q))",
             "    return best",
             ("tests/geometry/test_sweep.py", "tests/geometry/test_collision.py"), "the standing segment's end points are not turned back"),
    Mutation("sweep-no-crossing", "tables", "geometry/sweep.py",
             "        best = np.where(cut, 0.0, best)", "        best = best",
             ("tests/geometry/test_sweep.py", "tests/geometry/test_collision.py"), "an arc crossing the segment is not distance 0"),
    Mutation("reach-no-elbow", "tables", "geometry/alpha_beta.py",
             "out = max(out, math.sqrt(max(0.0, self.alpha**2 + r**2 + 2 * self.alpha * r * cmax)))",
             "out = max(out, r)",
             ("tests/geometry/test_sweep.py", "tests/geometry/test_collision.py"), "reach ignores the elbow (the bug of issue 13)"),
    Mutation("guards-not-symmetric", "tables", "planning/guards.py",
             "    out[m, at] |= w[rev[m], nxt[m, at]]  # the way back must be free too",
             "    pass",
             ("tests/planning/test_guards.py",), "blocked tables are not symmetrised (the lemma of the certificates)"),
    Mutation("validator-endpoints-only", "validator", "problems/validate_motion.py",
             "    samples = np.maximum(1, np.ceil(2 * top / resolution)).astype(np.int64)  # per step, from its pairs left",
             "    samples = np.ones(n_steps, dtype=np.int64)",
             ("tests/problems/test_validate.py", "tests/problems/test_validate_blocks.py", "tests/cli/test_safety.py"), "the validator checks only both ends of a step"),
    Mutation("validator-short-neighbours", "validator", "problems/validate_motion.py",
             "ia, ib = _close_pairs(self.bases, 2 * rmax + 2 * buf[:n].max(initial=0.0))",
             "ia, ib = _close_pairs(self.bases, rmax)",
             ("tests/problems/test_validate.py", "tests/cli/test_safety.py", "tests/cli/test_cli_check.py"),
             "the validator's neighbour bound misses pairs"),
    Mutation("planner-frozen-window-certificate", "planner certificates", "planning/windows.py",
             "            if len(members) == len(comp):\n"
             "                return WindowOutcome(\"infeasible\", members=comp,",
             "            if True:\n"
             "                return WindowOutcome(\"infeasible\", members=comp,",
             ("tests/planning/test_planner_oracle.py", "tests/planning/test_planner.py"),
             "a failed window with its neighbours frozen is taken as a certificate"),
    Mutation("planner-relaxed-frozen", "planner certificates", "planning/windows.py",
             "        R = wm.system(members, None, init=c, merged=True)",
             "        R = wm.system(members, c, init=c, merged=True)",
             ("tests/planning/test_planner_oracle.py", "tests/planning/test_planner.py"),
             "the relaxed sub-problem keeps the outsiders frozen (no longer a relaxation)"),
    Mutation("descent-not-serialisable", "planner", "planning/descent.py",
             "        if not _serialisable(T, k, side, c[p], mp, c[q], mq):",
             "        if False:",
             ("tests/planning/test_planner_oracle.py", "tests/planning/test_planner.py"),
             "the descent moves neighbours together without checking every order"),
    Mutation("timing-no-orders", "timing", "problems/timing.py",
             "    src = np.concatenate([early, precedes])\n    dst = np.concatenate([late, follows])",
             "    src, dst = precedes, follows",
             ("tests/problems/test_trajectories.py",),
             "a move does not wait for a neighbour's earlier move whose sweep can meet its own"),
    Mutation("timing-no-synchronisation", "timing", "problems/timing.py",
             "        start[m] = g_start[group[m]]\n        end[m] = start[m] + g_length[group[m]]",
             "        start[m] = ready[m]\n        end[m] = start[m] + duration[m]",
             ("tests/problems/test_trajectories.py",),
             "neighbours' moves of one step that can meet go at their own pace, not over one interval"),
    Mutation("sweeps-apart-half-slack", "timing", "geometry/sweeps_apart.py",
             "        slack = (la[pair] * ws + lb[pair] * wt) / 2",
             "        slack = (la[pair] * ws + lb[pair] * wt) / 4",
             ("tests/geometry/test_sweeps_apart.py",), "the Lipschitz bound of two motions at independent times is halved"),
    # issue 40: a plausible bug of each class the suite did not exercise, and the two weak catches
    Mutation("wrap-step-forgotten", "tables", "geometry/alpha_beta.py",
             "        if joint == 0 and self.alpha_range is None:\n"
             "            steps = np.append(steps, table[0] + 360.0 - table[-1])\n",
             "",
             ("tests/geometry/test_sweep_heterogeneous.py",),
             "the largest alpha step of an own angle table leaves out the step across 360° → 0°"),
    Mutation("timing-one-buffer-twice", "timing", "problems/timing.py",
             "problem.buffers[robot[a]] + problem.buffers[robot[b]])",
             "problem.buffers[robot[a]] + problem.buffers[robot[a]])",
             ("tests/problems/test_timing_buffers.py",), "the clearance of two moves is one robot's buffer twice"),
    Mutation("timing-waits-for-start", "timing", "problems/timing.py",
             "        np.maximum.at(ready, dst[lo:hi], end[src[lo:hi]])",
             "        np.maximum.at(ready, dst[lo:hi], start[src[lo:hi]])",
             ("tests/problems/test_timing_buffers.py",), "a move waits for its predecessors' start, not their end"),
    Mutation("descent-single-joints-unmerged", "planner", "planning/descent.py",
             "        if not mq and len(mp) < 2:", "        if not mq or len(mp) < 2:",
             ("tests/planning/test_descent_merged.py",),
             "two neighbours each turning one joint in one descent step are not checked together"),
    Mutation("resume-oom-inverted", "study", "study/resume.py",
             "(memory is None or memory >= case.memory_limit_mb)", "(memory is None or memory <= case.memory_limit_mb)",
             ("tests/study/test_study_resume.py",), "a case out of memory counts as done after its limit is raised"),
    Mutation("gen-range-short", "io", "des/io/gen_parser.py",
             "    return range(first, last + 1)", "    return range(first, last)",
             ("tests/des/test_gen_sections.py",), "a <Consecutive> range in a state set is read without its last state"),
    Mutation("saturation-no-final-pass", "reachability", "synthesis/reachability.py",
             "        if not dirty:\n"
             "            dirty = {j for j, cl in enumerate(clusters) if any(seen[i] != x for i in cl)}\n",
             "",
             ("tests/synthesis/test_reachability_within.py",), "saturation stops without checking that no cluster changes"),
]


def run(m: Mutation, timeout: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="supcoord-mutant-") as tmp:
        if HEAD_ONLY:  # the committed source, not the working tree
            archive = subprocess.run(["git", "archive", "HEAD", "src"], cwd=ROOT, capture_output=True, check=True)
            subprocess.run(["tar", "-x", "-C", tmp], input=archive.stdout, check=True)
        else:
            shutil.copytree(ROOT / "src", Path(tmp) / "src")
        path = Path(tmp) / "src" / "supcoord" / m.path
        text = path.read_text()
        if text.count(m.old) != 1:
            return {"status": f"pattern found {text.count(m.old)} times (update the mutation)", "test": "", "seconds": 0}
        path.write_text(text.replace(m.old, m.new))
        tests = [t for t in m.tests if (ROOT / t).exists()]
        env = dict(os.environ, PYTHONPATH=str(Path(tmp) / "src"), HYPOTHESIS_PROFILE="quick")
        cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "--no-header", "-rfE",
               "--timeout", "120", *tests]
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return {"status": "caught (the tests hung: time limit)", "test": "", "seconds": timeout}
        seconds = time.perf_counter() - t0
        failed = [line.split(" ")[1] for line in proc.stdout.splitlines() if line.startswith(("FAILED ", "ERROR "))]
        status = "caught" if proc.returncode != 0 else "SURVIVED"
        return {"status": status, "test": failed[0] if failed else ("" if proc.returncode == 0 else proc.stdout[-200:]),
                "seconds": seconds, "files": " ".join(tests)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="run the mutations whose id contains this text, or of this area "
                                   "(several: separated by commas)")
    ap.add_argument("--list", action="store_true", help="list the mutations and stop")
    ap.add_argument("--timeout", type=float, default=900, help="seconds per mutation (default 900)")
    ap.add_argument("--head", action="store_true", help="mutate the committed source (git HEAD), not the working tree")
    ap.add_argument("--out", type=Path, default=RESULTS, help=f"the results table (default {RESULTS.relative_to(ROOT)})")
    args = ap.parse_args()
    global HEAD_ONLY
    HEAD_ONLY = args.head
    wanted = args.only.split(",") if args.only else []
    chosen = [m for m in MUTATIONS if not wanted or any(w in m.id or w == m.area for w in wanted)]
    if args.list:
        for m in chosen:
            print(f"{m.id:36} {m.area:22} {m.path}: {m.what}")
        return 0
    rows, caught = [], 0
    for m in chosen:
        r = run(m, args.timeout)
        rows.append((m, r))
        print(f"{m.id:36} {r['status']:10} {r['seconds']:7.1f} s  {r['test']}", flush=True)
        caught = _write(args, rows, len(chosen))  # after each mutation: an interrupted run keeps its rows
    print(f"{caught}/{len(rows)} caught; wrote {args.out.resolve()}")
    return 0 if caught == len(rows) else 1


def _write(args: argparse.Namespace, rows: list[tuple[Mutation, dict]], chosen: int) -> int:
    """Write the results table of ``rows`` (of ``chosen`` mutations to run); the number caught."""
    caught = sum(r["status"].startswith("caught") for _, r in rows)
    lines = ["# Mutation testing", "",
             f"Command: `python benchmarks/mutations.py{' --head' if args.head else ''}"
             f"{' --only ' + args.only if args.only else ''}"
             f"{' --out ' + str(args.out) if args.out != RESULTS else ''}`  ",
             f"Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  ",
             f"Machine: {platform.node()} ({platform.machine()}, {os.cpu_count()} CPUs), "
             f"Python {platform.python_version()}, load {os.getloadavg()[0]:.2f}  ",
             f"Code: `{_version()}`", "",
             f"**{caught} of {len(rows)} mutations caught.**"
             + ("" if len(rows) == chosen else f" (run in progress or interrupted: {len(rows)} of {chosen} run)"), "",
             "| mutation | area | what it breaks | caught by | seconds |", "|---|---|---|---|---|"]
    for m, r in rows:
        by = f"`{r['test']}`" if r["status"] == "caught" and r["test"] else r["status"]
        lines.append(f"| `{m.id}` ({m.path}) | {m.area} | {m.what} | {by} | {r['seconds']:.0f} |")
    out = args.out.resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, out)
    return caught


def _version() -> str:
    try:
        return subprocess.run(["git", "describe", "--always", "--dirty"], cwd=ROOT, capture_output=True, text=True,
                              timeout=10).stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


if __name__ == "__main__":
    sys.exit(main())
