"""The adversarial campaign: thousands of mutated files through every reader and command.

Seeds are files supcoord writes (a PROBLEM.json and its PLAN.json, a rotary and an
alpha-beta problem, plants and specifications as ``.gen`` and JSON generators); each
case mutates one seed with :mod:`supcoord.testing.fuzz` (its seed number reproduces it)
and runs the command that reads it, in a worker process, with ``--timeout 20 --max-memory
2G``. Outcomes:

- *clean*: exit 0 (an answer), 2 with exactly one line on standard error that names the
  file, or 3 (a budget);
- *traceback*: an exception escaped (the console script would exit 1);
- *bad message*: exit 2 with several lines, or a line that does not name the file;
- *hang*: no answer within 60 s (the worker's alarm);
- *memory*: the worker's peak resident size grew by more than 3 GiB during the case.

Then the data-loss scenarios, through the real console script: an output that is an
input (plain, through a link, another spelling), a symbolic link, a FIFO and a missing or
read-only directory as ``--out``/``--export``, and an interrupted ``demo``; each must leave
every input byte-identical and no partial output.

    python benchmarks/fuzz_campaign.py                 # 2,800 cases, writes results/fuzz.md
    python benchmarks/fuzz_campaign.py --cases 200     # a quick look (prints only)
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import multiprocessing as mp
import os
import platform
import random
import resource
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "fuzz.md"
LIMITS = ["--timeout", "20", "--max-memory", "2G"]
THREE = {"layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
         "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12}, "collision": {"buffer": 2.0},
         "start": [0, 0, 0], "target": [6, 6, 6]}
AB = {"layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
      "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7},
      "collision": {"buffer": 2.0}, "start": [[0, 6]] * 7, "target": [[6, 6]] * 7}


def _main(argv: list[str]) -> tuple[int, str]:
    from supcoord.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, err.getvalue()


def make_seeds(d: Path) -> dict[str, bytes]:
    from supcoord.des.families import small_factories
    from supcoord.des.io import write_generator

    (d / "problem.json").write_text(json.dumps(THREE))
    (d / "ab.json").write_text(json.dumps(AB))
    _main(["solve", str(d / "problem.json"), "--out", str(d / "plan.json"), "--quiet"])
    plants, specs = small_factories(1)  # two machines and the buffer between them
    write_generator(plants[0], d / "plant.gen")
    write_generator(plants[1], d / "plant2.gen")
    write_generator(specs[0], d / "spec.gen")
    write_generator(plants[1], d / "plant.json")
    return {p.name: p.read_bytes() for p in d.iterdir()}


#: (label, seed file it mutates, mutator, the command line with FILE and OTHER placeholders)
KINDS = [
    ("problem (rotary)", "problem.json", "json", ["solve", "FILE", "--json", "--quiet"]),
    ("problem (alpha-beta)", "ab.json", "json", ["solve", "FILE", "--json", "--quiet"]),
    ("plan", "plan.json", "json", ["check", "OTHER:problem.json", "FILE", "--json", "--quiet"]),
    ("plant .gen (supcon)", "plant.gen", "gen", ["supcon", "--plant", "FILE", "OTHER:plant2.gen", "--spec",
                                                 "OTHER:spec.gen", "--json"]),
    ("spec .gen (supcon)", "spec.gen", "gen", ["supcon", "--plant", "OTHER:plant.gen", "OTHER:plant2.gen", "--spec",
                                               "FILE", "--json"]),
    (".gen (force)", "plant.gen", "gen", ["force", "FILE", "--json", "--quiet"]),
    ("JSON generator (supcon)", "plant.json", "json", ["supcon", "--plant", "FILE", "--json", "--quiet"]),
]


def run_case(args: tuple[int, int, str]) -> tuple[int, str, str, str]:
    """One case in this worker: ``(kind index, seed, seeds dir)`` → ``(kind, seed, outcome, detail)``."""
    from supcoord.testing.fuzz import mutate_gen, mutate_json

    k, seed, seeds_dir = args
    label, name, how, argv = KINDS[k]
    seeds = Path(seeds_dir)
    with tempfile.TemporaryDirectory(prefix="fuzz-") as tmp:
        path = Path(tmp) / name
        data = (seeds / name).read_bytes()
        path.write_bytes((mutate_gen if how == "gen" else mutate_json)(data, random.Random(seed)))
        line = [str(path) if a == "FILE" else str(seeds / a[6:]) if a.startswith("OTHER:") else a for a in argv]
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        signal.signal(signal.SIGALRM, _hang)
        signal.alarm(60)
        try:
            code, err = _main(line + LIMITS)
        except _Hang:
            return k, seed, "hang", ""
        except BaseException as exc:  # noqa: BLE001 (every escape is the defect we count)
            return k, seed, "traceback", f"{type(exc).__name__}: {str(exc)[:120]}"
        finally:
            signal.alarm(0)
        grown = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) * 1024
        if grown > 3 * 2**30:
            return k, seed, "memory", f"{grown / 2**30:.1f} GiB"
        if code == 2 and (len(err.strip().splitlines()) != 1 or name not in err):
            return k, seed, "bad message", err.strip()[:160]
        if code not in (0, 2, 3):
            return k, seed, "traceback", f"exit {code}: {err.strip()[:120]}"
        return k, seed, f"clean (exit {code})", ""


class _Hang(Exception):
    pass


def _hang(signum, frame):  # noqa: ARG001
    raise _Hang


def data_loss(seeds: Path) -> list[tuple[str, bool, str]]:
    """The output-safety scenarios through the console script: ``(scenario, safe, detail)``."""
    exe = [sys.executable, "-m", "supcoord.cli"]
    out = []
    with tempfile.TemporaryDirectory(prefix="fuzz-loss-") as tmp:
        d = Path(tmp)
        os.symlink("problem.json", d / "link.json")
        os.mkfifo(d / "fifo")
        (d / "elsewhere.json").write_text("keep")
        os.symlink("elsewhere.json", d / "out-link.json")
        cases = [
            ("solve --out = the problem", ["solve", "problem.json", "--out", "problem.json"]),
            ("solve --out = the problem, another spelling", ["solve", "problem.json", "--out", "./problem.json"]),
            ("solve reading a link, --out = its target", ["solve", "link.json", "--out", "problem.json"]),
            ("solve --out = a symbolic link", ["solve", "problem.json", "--out", "out-link.json"]),
            ("solve --out = a FIFO", ["solve", "problem.json", "--out", "fifo"]),
            ("solve --out in a missing directory", ["solve", "problem.json", "--out", "no/such/plan.json"]),
            ("supcon --export = a plant", ["supcon", "--plant", "plant.gen", "plant2.gen", "--spec", "spec.gen",
                                           "--export", "plant.gen"]),
            ("supcon --export = a FIFO", ["supcon", "--plant", "plant.gen", "plant2.gen", "--spec", "spec.gen",
                                          "--export", "fifo"]),
            ("check --figure = the problem", ["check", "problem.json", "problem.json", "--figure", "problem.json"]),
        ]
        for label, argv in cases:
            for name in ("problem.json", "plant.gen", "plant2.gen", "spec.gen"):  # each scenario starts afresh
                (d / name).write_bytes((seeds / name).read_bytes())
            before = {p.name: p.read_bytes() for p in d.iterdir() if p.is_file() and not p.is_symlink()}
            try:
                proc = subprocess.run(exe + argv, cwd=d, capture_output=True, text=True, timeout=60)
                after = {p.name: p.read_bytes() for p in d.iterdir() if p.is_file() and not p.is_symlink()}
                changed = [n for n in before if after.get(n) != before[n]]
                stray = sorted(set(after) - set(before))
                safe = proc.returncode == 2 and not changed and not stray
                out.append((label, safe, f"exit {proc.returncode}; {proc.stderr.strip()[:100]}"
                            + (f"; changed {changed}" if changed else "") + (f"; left {stray}" if stray else "")))
            except subprocess.TimeoutExpired:
                out.append((label, False, "hung"))
        demo = subprocess.Popen(exe + ["demo", "--out", "demo-dir"], cwd=d, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE)
        time.sleep(1.0)
        demo.send_signal(signal.SIGINT)
        demo.wait(60)
        out.append(("demo interrupted after 1 s", not (d / "demo-dir").exists() or demo.returncode == 0,
                    f"exit {demo.returncode}; directory {'left' if (d / 'demo-dir').exists() else 'absent'}"))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=2800, help="mutated files in all (default 2800)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0, help="first mutation seed")
    args = ap.parse_args()
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="fuzz-seeds-") as tmp:
        seeds = Path(tmp)
        make_seeds(seeds)
        jobs = [(i % len(KINDS), args.seed + i, str(seeds)) for i in range(args.cases)]
        with mp.get_context("spawn").Pool(args.workers, maxtasksperchild=200) as pool:
            results = list(pool.imap_unordered(run_case, jobs, chunksize=8))
        loss = data_loss(seeds)
    seconds = time.perf_counter() - t0
    table = Counter((KINDS[k][0], outcome) for k, _, outcome, _ in results)
    outcomes = sorted({o for _, o, _, _ in [(0, r[2], 0, 0) for r in results]} | {"traceback", "hang", "memory",
                                                                                 "bad message"})
    defects = [r for r in results if not r[2].startswith("clean")]
    lines = ["# Fuzz campaign", "",
             f"Command: `python benchmarks/fuzz_campaign.py --cases {args.cases} --workers {args.workers}"
             f" --seed {args.seed}`  ",
             f"Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {seconds:.0f} s  ",
             f"Machine: {platform.node()} ({platform.machine()}, {os.cpu_count()} CPUs), Python "
             f"{platform.python_version()}, load {os.getloadavg()[0]:.2f}  ",
             f"Code: `{_version()}`", "",
             f"**{len(results)} runs: tracebacks {sum(r[2] == 'traceback' for r in results)}, hangs "
             f"{sum(r[2] == 'hang' for r in results)}, memory blow-ups {sum(r[2] == 'memory' for r in results)}, "
             f"bad messages {sum(r[2] == 'bad message' for r in results)}; data-loss paths "
             f"{sum(not s for _, s, _ in loss)} of {len(loss)}.**", "",
             "| reader (command) | " + " | ".join(outcomes) + " |", "|---|" + "---|" * len(outcomes)]
    for label, *_ in KINDS:
        lines.append(f"| {label} | " + " | ".join(str(table[(label, o)]) for o in outcomes) + " |")
    lines += ["", "| data-loss scenario | safe | what happened |", "|---|---|---|"]
    lines += [f"| {label} | {'yes' if safe else '**NO**'} | {detail.replace('|', '/')} |" for label, safe, detail in loss]
    if defects:
        lines += ["", "Defects (kind, mutation seed, detail):", ""]
        lines += [f"- {KINDS[k][0]}, seed {seed}: {outcome} {detail}" for k, seed, outcome, detail in defects[:50]]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.cases >= 2000:
        tmp_path = RESULTS.with_suffix(".md.tmp")
        tmp_path.write_text(text)
        os.replace(tmp_path, RESULTS)
        print(f"wrote {RESULTS.relative_to(ROOT)}")
    return 0 if not defects and all(s for _, s, _ in loss) else 1


def _version() -> str:
    try:
        return subprocess.run(["git", "describe", "--always", "--dirty"], cwd=ROOT, capture_output=True, text=True,
                              timeout=10).stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


if __name__ == "__main__":
    sys.exit(main())
