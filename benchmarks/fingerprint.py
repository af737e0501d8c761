"""Fingerprint of supcoord's results, to show that a refactoring changed no answer.

Runs a fixed set of deterministic computations through the public API and the command
line only (so the same script runs against any release), and writes their results as
JSON, minus timings and memory:

- ``solve`` (``improve=0``, so no wall-clock budget shapes the plan) on random rotary
  and SDSS-V alpha-beta hex grids and the shipped examples, both routes where the
  monolithic one is small enough: status, configurations, events, makespan, certificate,
  window and node statistics;
- the seed paper's example (supcon statistics, CCC in both semantics, the witness) and
  its literal model at 3, 50 and 300 positioners;
- the command line's JSON: ``supcon`` on every classic model (and the exported ``.gen``
  text), ``force`` in both semantics, ``paper``, ``demo``, ``solve`` and ``check`` on the
  examples.

Compare two fingerprints with ``--compare``: BDD node peaks are sampled at time-throttled
budget checks and may differ by a node or two between identical runs, so they are
compared within 1 %; CUDD's cache counters (lookups, hits, insertions) hash node
addresses and vary between identical runs, so they are left out; everything else must be equal.

    python benchmarks/fingerprint.py before.json                 # with one version installed
    python benchmarks/fingerprint.py after.json                  # with the other
    python benchmarks/fingerprint.py --compare before.json after.json
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from importlib import resources
from pathlib import Path
from typing import Any

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
# keys whose values depend on the machine and its load; CUDD's cache counters depend on node
# addresses (its computed table hashes pointers), so they differ between identical runs
UNSTABLE = ("second", "timing", "rss", "elapsed", "cudd_")


def _jsonable(value: Any) -> Any:
    return json.loads(json.dumps(value, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))


def _stable(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _stable(v) for k, v in x.items()
                if not any(u in k for u in UNSTABLE) and k not in ("command", "files")}
    if isinstance(x, list):
        return [_stable(v) for v in x]
    return x


def _plan(plan: Any) -> dict[str, Any]:
    out = {"status": plan.status, "reason": getattr(plan, "reason", None), "stats": getattr(plan, "stats", {})}
    for attr in ("configurations", "events", "makespan", "lower_bound"):
        out[attr] = getattr(plan, attr, None)
    return _stable(_jsonable(out))


def _cli(*args: str) -> Any:
    r = subprocess.run([sys.executable, "-m", "supcoord.cli", *args, "--json"], capture_output=True, text=True,
                       env=os.environ)
    try:
        return [r.returncode, _stable(json.loads(r.stdout))]
    except json.JSONDecodeError:
        return [r.returncode, r.stdout[-500:], r.stderr[-500:]]


def _problems(sc: Any) -> list[tuple[str, Any]]:
    cases = [("rotary-hex2", sc.random_problem({"kind": "hex", "rings": 2, "pitch": 22.4},
                                               {"kind": "rotary", "arm": 15.0, "steps": 12}, 1.0, seed))
             for seed in range(4)]
    cases += [("sdss-v-r2", sc.preset_problem("sdss-v", rings=2, seed=seed, alpha_steps=12, beta_steps=7))
              for seed in range(3)]
    cases.append(("sdss-v-r3", sc.preset_problem("sdss-v", rings=3, seed=3, alpha_steps=12, beta_steps=7)))
    for name in ("three_rotary", "infeasible_triangle", "hex19_rotary", "sdss_v_unfold"):
        cases.append((name, sc.load_problem(EXAMPLES / f"{name}.json")))
    return cases


def fingerprint() -> dict[str, Any]:
    import supcoord as sc

    out: dict[str, Any] = {}
    for i, (name, problem) in enumerate(_problems(sc)):
        for route in ("local", "monolithic"):
            if route == "monolithic" and problem.n > 7:
                continue
            try:
                out[f"solve/{name}/{i}/{route}"] = _plan(sc.solve(problem, route=route, improve=0))
            except sc.SupcoordError as exc:
                out[f"solve/{name}/{i}/{route}"] = f"{type(exc).__name__}: {exc}"
        print(f"solved {name} ({i})", file=sys.stderr)
    G, E = sc.coupled_models(sc.CoupledModel(sc.paper_example()))
    result = sc.supcon(G, E)
    verdict = sc.ccc(result.supervisor)
    out["paper_example/supcon"] = _stable(_jsonable(result.stats))
    out["paper_example/ccc"] = [verdict.forcible, verdict.rank, verdict.witness]
    out["paper_example/ccc_standard"] = sc.ccc(result.supervisor, "standard").forcible
    for n in (3, 50, 300):
        out[f"run_paper/{n}"] = _stable(_jsonable(sc.run_paper(n, 12).payload))
    classic = resources.files("supcoord") / "data" / "classic"
    for folder in sorted(p for p in classic.iterdir() if p.is_dir()):
        meta = json.loads((folder / "model.json").read_text())
        out[f"cli/supcon/{folder.name}"] = _cli("supcon", "--plant", *[str(folder / f) for f in meta["plants"]],
                                                "--spec", *[str(folder / f) for f in meta["specs"]])
    for n, model in ((4, "literal"), (3, "coupled"), (100, "literal")):
        out[f"cli/paper/{n}/{model}"] = _cli("paper", "--positioners", str(n), "--steps", "8", "--model", model)
    out["cli/demo"] = _cli("demo", "--no-files")
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("three_rotary", "hex19_rotary", "infeasible_triangle"):
            plan = Path(tmp) / f"{name}.plan.json"
            out[f"cli/solve/{name}"] = _cli("solve", str(EXAMPLES / f"{name}.json"), "--out", str(plan))
            if plan.exists():
                out[f"cli/check/{name}"] = _cli("check", str(EXAMPLES / f"{name}.json"), str(plan))
        factory = classic / "small_factory"
        meta = json.loads((factory / "model.json").read_text())
        V = Path(tmp) / "V.gen"
        out["cli/supcon-export"] = _cli("supcon", "--plant", *[str(factory / f) for f in meta["plants"]],
                                        "--spec", *[str(factory / f) for f in meta["specs"]], "--export", str(V))
        out["cli/V.gen"] = V.read_text()
        out["cli/force"] = _cli("force", str(V))
        out["cli/force-standard"] = _cli("force", str(V), "--semantics", "standard")
    return _jsonable(out)


def differences(a: Any, b: Any, path: str = "") -> list[str]:
    """Where ``a`` and ``b`` differ (node counts within 1 %)."""
    if type(a) is not type(b):
        return [f"{path}: {str(a)[:80]} | {str(b)[:80]}"]
    if isinstance(a, dict):
        out = [f"{path}/{k}: only in {'first' if k in a else 'second'}" for k in sorted(set(a) ^ set(b))]
        for k in sorted(set(a) & set(b)):
            out += differences(a[k], b[k], f"{path}/{k}")
        return out
    if isinstance(a, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} | {len(b)}"]
        return [d for i, (u, v) in enumerate(zip(a, b)) for d in differences(u, v, f"{path}[{i}]")]
    if a != b and not (isinstance(a, (int, float)) and "nodes" in path and abs(a - b) <= 0.01 * max(abs(a), abs(b))):
        return [f"{path}: {str(a)[:80]} | {str(b)[:80]}"]
    return []


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", help="write the fingerprint here (JSON)")
    ap.add_argument("--compare", nargs=2, metavar=("A.json", "B.json"), help="compare two fingerprints")
    args = ap.parse_args()
    if args.compare:
        a, b = (_stable(json.loads(Path(p).read_text())) for p in args.compare)
        diffs = differences(a, b)
        print("\n".join(diffs) or f"identical: {len(a)} entries")
        return 1 if diffs else 0
    if not args.out:
        ap.error("give an output file or --compare A B")
    data = fingerprint()
    out = Path(args.out)
    with tempfile.NamedTemporaryFile("w", dir=out.resolve().parent, suffix=".tmp", delete=False) as tmp:
        json.dump(data, tmp, indent=1, sort_keys=True)
    os.replace(tmp.name, out)  # atomic: an interrupted run leaves the old file
    print(f"{len(data)} entries written to {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
