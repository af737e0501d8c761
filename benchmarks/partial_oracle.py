"""Partial plans against the independent oracle on small random problems with no complete plan.

For each case of :func:`supcoord.testing.partial_cases.tight_case` (3-6 rotary robots packed
tighter than any instrument, no single-move plan puts every robot on target):

- ``solve`` (defaults) must answer ``partial``;
- two oracle maxima (:mod:`supcoord.testing.oracle.subsets`): with the robots off target at
  their starts (its exhaustive search over subsets), and with them anywhere they can be
  brought (one search over every reachable configuration).  Where the plan claims
  ``optimal``, its count must be at least the first (equal where it parks no robot); everywhere
  the second must lie between the plan's count and its ``on_target_bound``;
- the plan must pass the validator (``validate_plan``) and the oracle's own replay of the
  schedule (``oracle_check_steps`` on the problem ending where the plan says);
- every certificate named by a robot off target must be unsolvable for the oracle.

Writes one row per case and the totals to a JSON file, and a short Markdown table beside it.

    python benchmarks/partial_oracle.py --cases 300 --out benchmarks/results/partial_oracle.json
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from supcoord.planning import solve
from supcoord.problems.problem import parse_problem
from supcoord.problems.validate import validate_plan
from supcoord.testing.oracle import oracle_check_steps
from supcoord.testing.oracle.subsets import (ends_at_start, oracle_group_unsolvable, oracle_most_on_target,
                                              oracle_most_on_target_anywhere)
from supcoord.testing.partial_cases import tight_cases


def check_case(seed: int, data: dict) -> dict:
    """One case: the plan, the oracle's answer and every check (``ok`` when all hold)."""
    problem = parse_problem(data)
    t0 = time.perf_counter()
    plan = solve(problem)
    seconds = time.perf_counter() - t0
    best = oracle_most_on_target(data)
    anywhere = oracle_most_on_target_anywhere(data)
    parked = {e.robot: list(e.at) for e in plan.off_target if e.end == "parked"}
    row = {"seed": seed, "robots": problem.n, "steps": data["kinematics"]["steps"], "status": plan.status,
           "on_target": plan.on_target, "oracle_on_target": best.on_target,
           "oracle_on_target_anywhere": anywhere, "parked": {str(r): at for r, at in parked.items()},
           "optimal": plan.optimal,
           "on_target_bound": plan.on_target_bound, "off_target": [e.robot for e in plan.off_target],
           "method": plan.stats.get("partial", {}).get("method"), "seconds": round(seconds, 3)}
    failures = []
    if plan.status != "partial":
        failures.append(f"status {plan.status}")
    else:
        if plan.optimal and (plan.on_target < best.on_target or (not parked and plan.on_target != best.on_target)):
            failures.append(f"optimal claimed with {plan.on_target} on target, oracle {best.on_target}")
        if not plan.on_target <= anywhere <= plan.on_target_bound:
            failures.append(f"oracle (anywhere) {anywhere} outside [{plan.on_target}, {plan.on_target_bound}]")
        if not validate_plan(problem, plan).valid:
            failures.append("the validator refuses the plan")
        ends = ends_at_start(data, [e.robot for e in plan.off_target])
        for r, at in parked.items():
            ends["target"][r] = at[0] if isinstance(ends["target"][r], int) else at
        if oracle_check_steps(ends, plan.configurations) is not None:
            failures.append("the oracle refuses the plan's steps")
        for e in plan.off_target:
            c = e.certificate
            if c is None or not oracle_group_unsolvable(data, c.members, c.at_start):
                failures.append(f"robot {e.robot}: certificate {c} not confirmed")
    row["failures"] = failures
    row["ok"] = not failures
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=300)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--out", default="benchmarks/results/partial_oracle.json")
    args = parser.parse_args()
    t0 = time.perf_counter()
    rows = []
    for seed, data in tight_cases(args.cases, args.first_seed):
        rows.append(check_case(seed, data))
        print(json.dumps(rows[-1]), flush=True)
    total = {"cases": len(rows), "ok": sum(r["ok"] for r in rows),
             "optimal_claimed": sum(bool(r["optimal"]) for r in rows),
             "equal_to_oracle": sum(r["on_target"] == r["oracle_on_target"] for r in rows),
             "oracle_anywhere_above_at_start": sum(r["oracle_on_target_anywhere"] > r["oracle_on_target"]
                                                   for r in rows),
             "equal_to_oracle_anywhere": sum(r["on_target"] == r["oracle_on_target_anywhere"] for r in rows),
             "parked": sum(bool(r["parked"]) for r in rows),
             "by_method": {m: sum(r["method"] == m for r in rows) for m in sorted({str(r["method"]) for r in rows})},
             "robots": {str(k): sum(r["robots"] == k for r in rows) for k in range(3, 7)},
             "seconds_solve": round(sum(r["seconds"] for r in rows), 1),
             "seconds_all": round(time.perf_counter() - t0, 1)}
    out = Path(args.out)
    out.write_text(json.dumps({"totals": total, "cases": rows}, indent=1) + "\n")
    lines = ["# Partial plans against the independent oracle", "",
             f"`python benchmarks/partial_oracle.py --cases {args.cases} --first-seed {args.first_seed}`", "",
             "| cases | all checks hold | optimal claimed | on target = oracle maximum (off target at starts) | "
             "oracle maximum anywhere > at starts | on target = oracle maximum anywhere | plans that park | "
             "solve time (s) |",
             "|---|---|---|---|---|---|---|---|",
             f"| {total['cases']} | {total['ok']} | {total['optimal_claimed']} | {total['equal_to_oracle']} | "
             f"{total['oracle_anywhere_above_at_start']} | {total['equal_to_oracle_anywhere']} | {total['parked']} | "
             f"{total['seconds_solve']} |", "",
             f"Robots per case: {total['robots']}; method: {total['by_method']}."]
    bad = [r for r in rows if not r["ok"]]
    lines += ["", "Failures:" if bad else "No failures."] + [f"- seed {r['seed']}: {r['failures']}" for r in bad]
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    print(json.dumps(total))


if __name__ == "__main__":
    main()
