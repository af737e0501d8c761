"""Collision tables of the real APO wok: time, memory and the tables' fingerprint, side by side.

For each lattice and each source (this checkout, and with ``--rev`` older revisions exported
by ``git archive``), a fresh process builds kaiju's instance on the ``sdss-v-apo`` layout and
times ``problem.tables().prepare(range(PAIRS))`` (every robot has its own geometry, so every
pair has its own tables: :mod:`supcoord.geometry.batch`).  It reports seconds, ms a pair, the
packed tables' size, the peak and final RSS, and a SHA-1 of every static and swept table it
built: equal fingerprints mean the revisions computed the same Booleans.  The sources run one
after the other in one invocation, so the ratios compare like with like.  Last, segment
distances timed in one pass and in blocks (why the tables are computed in blocks).  Writes
``results/tables.md`` with the command, machine and load.

    python benchmarks/bench_tables.py                                  # 37x19, 512 pairs
    python benchmarks/bench_tables.py --steps 19x10,37x19 --pairs 512 --rev 1acbad4
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

CHILD = r"""
import hashlib, json, resource, sys, time
sys.path.insert(0, sys.argv[1])
from bench_instrument import problem_json
from supcoord.problems.problem import parse_problem
instance = json.loads(open(sys.argv[2]).read())
steps = tuple(int(v) for v in sys.argv[3].split("x"))
problem = parse_problem(problem_json(instance, steps, "unfold"), "apo")
tables = problem.tables()
pairs = range(min(int(sys.argv[4]), len(problem.pairs)))
t0, c0 = time.perf_counter(), time.process_time()
tables.prepare(pairs)
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
final = int(open("/proc/self/statm").read().split()[1]) * 4096 / 2**20
digest = hashlib.sha1()
for k in pairs:
    for table in (tables.static(k), tables.swept(k, 0), tables.swept(k, 1)):
        digest.update(table.shape.__repr__().encode())
        digest.update(__import__("numpy").packbits(table).tobytes())
packed = sum(v[0].nbytes for v in tables._bits._packed.values()) / 2**20
print(json.dumps({"pairs": len(pairs), "wall_s": wall, "cpu_s": cpu, "packed_mib": packed, "peak_rss_mb": peak,
                  "final_rss_mb": final, "sha1": digest.hexdigest()[:12]}))
"""


BLOCKS = r"""
import json, time
import numpy as np
from supcoord.geometry import segments
rng = np.random.default_rng(0)
out = {}
for n in (4_000, 60_000, 500_000):
    c = rng.normal(size=(8, n)) * 10
    reps = max(1, 2_000_000 // n)
    for name, f in (("one pass", segments._segment_distance_xy), ("blocks", segments.segment_distance_xy)):
        t = time.perf_counter()
        for _ in range(reps):
            f(*c)
        out[f"{n} {name}"] = (time.perf_counter() - t) / reps / n * 1e9
print(json.dumps(out))
"""


def _export(rev: str, into: Path) -> Path:
    """``src`` and ``benchmarks`` of git revision ``rev`` in ``into``."""
    archive = into / f"{rev}.tar"
    subprocess.run(["git", "-C", str(ROOT), "archive", "-o", str(archive), rev, "src", "benchmarks"], check=True)
    with tarfile.open(archive) as tar:
        tar.extractall(into / rev, filter="data")
    return into / rev


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instance", default=str(HERE / "results" / "kaiju_instances" / "apo_s0.json"))
    ap.add_argument("--steps", default="37x19", help="comma-separated AxB lattices")
    ap.add_argument("--pairs", type=int, default=512, help="the first PAIRS neighbour pairs (3713 = all)")
    ap.add_argument("--rev", action="append", default=[], help="also an older git revision (repeatable)")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds per case")
    ap.add_argument("--out", default=str(HERE / "results" / "tables.md"))
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    from supcoord.geometry.segments import BLOCK as BLOCK_SIZE
    from supcoord.study.machine import code_version, cpu_model, load, machine

    rows = []
    load_before = load()
    with tempfile.TemporaryDirectory() as tmp:
        sources = [("this checkout", ROOT)] + [(rev, _export(rev, Path(tmp))) for rev in args.rev]
        for text in args.steps.split(","):
            for name, root in sources:
                cmd = [sys.executable, "-c", CHILD, str(root / "benchmarks"), args.instance, text, str(args.pairs)]
                env = {"PYTHONPATH": str(root / "src"), "PATH": "/usr/bin:/bin"}
                try:
                    out = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout, env=env)
                    res = json.loads(out.stdout.strip().splitlines()[-1]) if out.returncode == 0 else \
                        {"error": out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode}
                except subprocess.TimeoutExpired:
                    res = {"error": f"timeout {args.timeout:g} s"}
                row = {"steps": text, "source": name, **res}
                rows.append(row)
                print(json.dumps(row), flush=True)
    lines = ["# Collision tables of SDSS-V's APO wok (kaiju's instance), side by side", "",
             f"Command: `python benchmarks/bench_tables.py {' '.join(sys.argv[1:])}`; supcoord {code_version()}.", "",
             f"Machine: {machine()}, {cpu_model()}; load {load_before} before, {load()} after; "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. Each case in a fresh process, one after "
             "the other; `problem.tables().prepare(range(pairs))`; the fingerprint is a SHA-1 of every static and "
             "swept table built (equal: the same Booleans).", "",
             "| positions | source | pairs | wall s | CPU s | ms a pair | packed MiB | peak RSS MB | final RSS MB | fingerprint |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['steps']} | {r['source']} | error: {r['error']} | | | | | | | |")
            continue
        lines.append(f"| {r['steps']} | {r['source']} | {r['pairs']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} | "
                     f"{1000 * r['wall_s'] / max(r['pairs'], 1):.1f} | {r['packed_mib']:.0f} | {r['peak_rss_mb']:.0f} | "
                     f"{r['final_rss_mb']:.0f} | {r['sha1']} |")
    # why the tables are computed in blocks: numpy's long temporaries are fresh memory maps
    out = subprocess.run([sys.executable, "-c", BLOCKS], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"})
    per = json.loads(out.stdout.strip().splitlines()[-1])
    lines += ["", f"Segment distances, ns each (`segments.segment_distance_xy` in blocks of "
                  f"{BLOCK_SIZE:,}, against one pass over the whole arrays):", "",
              "| segment pairs | one pass | blocks |", "|---|---|---|"]
    for n in (4_000, 60_000, 500_000):
        lines.append(f"| {n:,} | {per[f'{n} one pass']:.0f} | {per[f'{n} blocks']:.0f} |")
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
