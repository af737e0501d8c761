"""The readable report of ``supcoord demo`` (:func:`report`), from :func:`supcoord.paper.demo.run_demo`'s payload."""

from __future__ import annotations

from typing import Any

__all__ = ["report"]


def _supervisor_line(s: dict[str, Any]) -> str:
    return (f"  V = supcon(G, allevents(G)||S): {s['states']} states, {s['transitions']} transitions, "
            f"{s['marked']} marked, {s['bdd_nodes']} BDD nodes")


def report(p: dict[str, Any]) -> str:
    """The readable report of :func:`run_demo`'s payload."""
    inst, lit, cou = p["instance"], p["literal"], p["coupled"]
    L: list[str] = []
    add = L.append
    add("supcoord demo — the seed paper's example (Macktoobian, Gillet, Kneib, IFAC LSS 2019)")
    add("")
    add(f"Positioners P1, P2, P3 on the first three hex sites (mutual neighbours), n = {inst['steps']} positions "
        f"({360 // inst['steps']}° steps), priorities 1 > 2 > 3 (P1 highest).")
    add(f"  start  {inst['start']}    target {inst['target']}")
    g = inst["geometry"]
    add(f"  arms {g['arm']} mm, pitch {g['pitch']} mm, safety zone {g['zone']} mm, hard collision < {2 * g['buffer']} mm")
    add("")
    add("Literal reading (the paper's G^P, S^P as written; k, e free to fire):")
    pe = lit["priority_events"]
    add(f"  priority events: P1 {pe['P1']}, P2 {pe['P2']}, P3 {pe['P3']} (static, among both neighbours)")
    add(f"  G = ||G^P: {lit['plant_states']} reachable states")
    add(_supervisor_line(lit["supervisor"]))
    v = lit["verdict"]
    add(f"  CCC: preemptive {'forcible' if v['preemptive'] else 'NOT forcible'}, "
        f"standard {'forcible' if v['standard'] else 'NOT forcible'} "
        f"(forcible layers: {lit['ccc']['preemptive']['layers']})")
    add("  Why: k and e are defined at every free state, so the environment can answer any move with")
    add("  k, e, k, e, ... forever; no state off the target is forcible under either semantics.")
    add("")
    add("Coupled reading (k pending exactly when a neighbour's arm enters the zone, e when it empties):")
    add(f"  G (coupled plant): {cou['plant_states']} reachable states")
    add(_supervisor_line(cou["supervisor"]))
    c = cou["ccc"]
    add(f"  CCC (preemptive): {'forcible' if c['forcible'] else 'NOT forcible'}, rank {c['rank']}, "
        f"layers {c['layers']}")
    st = cou["standard"]
    add(f"  CCC (standard):   {'forcible' if st['forcible'] else 'NOT forcible'}, rank {st['rank']}")
    add(f"  shortest forcing path: <{', '.join(c['witness'])}>")
    for k, r in enumerate(cou["witness_explained"], 1):
        where = ", ".join(f"P{i + 1}@{q}" + (f"^{l}" if l else "") for i, (q, l) in enumerate(zip(r["position"], r["level"])))
        add(f"   {k:2d}. {r['event']:>4}  {r['text']:<62} -> {where}")
    add(f"  ends with every arm on target and every zone empty: {cou['witness_reaches_target']}; "
        f"replayed in V, ends in V's marked state: {cou['witness_replays_in_V']}")
    add("")
    add("The paper's path <73, 10, 30, 15, 31, 81, 20>, replayed:")
    add("  literal model:")
    for r in lit["paper_path"]:
        if r["defined"]:
            add(f"    {r['event']:>4}  {r['text']:<62} G^P: {' '.join(r['plant'])}  S^P: {' '.join(r['spec'])}")
        else:
            add(f"    {r['event']:>4}  NOT DEFINED: {r['why']}")
    last = lit["paper_path"][-1]
    add(f"    ends marked: {last.get('marked', False)} (the last event is k = 20: P2 is left in collision mode,")
    add("    and S^P never sees h/l, so P1 and P3 are not where their specifications think they are)")
    add("  coupled model:")
    for r in cou["paper_path"]:
        if r["defined"]:
            where = ", ".join(f"P{i + 1}@{q}" + (f"^{l}" if l else "") for i, (q, l) in enumerate(zip(r["position"], r["level"])))
            add(f"    {r['event']:>4}  {r['text']:<62} -> {where}")
            if r.get("preempted_by"):
                add(f"          (under the paper's Remark this move is preempted: collision/free events of "
                    f"{', '.join(r['preempted_by'])} are pending)")
        else:
            add(f"    {r['event']:>4}  NOT DEFINED: {r['why']}")
    if p.get("files"):
        add("")
        add("Files: " + ", ".join(f"{k} {v}" for k, v in p["files"].items()))
    return "\n".join(L)
