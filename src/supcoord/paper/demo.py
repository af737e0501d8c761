"""The seed paper's 3-positioner example end to end, in both readings (``supcoord demo``).

For the literal reading (:mod:`.literal`) and the coupled one (:mod:`.coupled`):
``G = ||G^P``, ``S = ||S^P``, ``V = supcon(G, allevents(G) || S)``, ``CCC(V)`` with
preemptive semantics (and standard, for comparison), the shortest forcing string in
Table-1 labels explained event by event, and a replay of the paper's reported path
``⟨73, 10, 30, 15, 31, 81, 20⟩`` in both models.  Writes the coupled reading's
``G.gen``, ``S.gen``, ``V.gen`` and a figure.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (the seed paper, Section 4).
"""

from __future__ import annotations

import contextlib
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from ..bdd.context import Context
from ..des import explicit_ops as XO
from ..des.symbolic import to_explicit
from ..errors import InputError
from ..outputs import atomic_output, check_output
from ..synthesis import ccc, reachable, supcon
from .coupled import CoupledModel, Geometry, coupled_models, plant_explicit
from .demo_report import report
from .literal import CONTROLLABLE, PaperInstance, decode_label, literal_models, paper_example, spec_explicit

__all__ = ["PAPER_PATH", "EXAMPLE_STEPS", "EXAMPLE_TARGET", "DemoResult", "run_demo", "replay_coupled",
           "replay_literal", "replay_in", "describe", "draw_demo"]

#: the forcible path the paper reports for its example
PAPER_PATH = ("73", "10", "30", "15", "31", "81", "20")
#: the example's number of positions and targets (docs/paper.md explains the choice)
EXAMPLE_STEPS = 8
EXAMPLE_TARGET = (1, 5, 5)

_WORDS = {
    "v": "turns clockwise (forward, v)",
    "w": "turns counter-clockwise (backward, w)",
    "h": "escapes clockwise by priority (h)",
    "l": "yields counter-clockwise by priority (l)",
    "m": "acknowledges that a peer left its zone (m)",
    "k": "registers a neighbour in its safety zone (collision, k)",
    "e": "has its safety zone empty again (free, e)",
}


_SHORT = {"v": "turns clockwise", "w": "turns counter-clockwise", "h": "escapes clockwise (priority)",
          "l": "yields counter-clockwise (priority)", "m": "waits (priority)", "k": "neighbour enters its zone",
          "e": "its zone is empty again"}


def describe(label: str) -> str:
    """``"P1 turns counter-clockwise (backward, w)"`` for label ``73``."""
    num, kind = decode_label(label)
    return f"P{num} {_WORDS[kind]}"


# -- replays ------------------------------------------------------------------------


def replay_coupled(model: CoupledModel, labels: Sequence[str]) -> list[dict[str, Any]]:
    """Run ``labels`` from the start in the coupled plant; one record per event (stops at
    the first event that is not defined)."""
    inst = model.inst
    pos, lvl = tuple(inst.start), (0,) * inst.size
    out = []
    for lab in labels:
        num, kind = decode_label(lab)
        i = num - 1
        if i >= inst.size:
            raise InputError(f"event {lab} belongs to P{num}, outside the instance", value=lab)
        succ = model.successors(i, pos, lvl)
        pending = [j + 1 for j in range(inst.size) if {"k", "e"} & set(model.successors(j, pos, lvl))]
        rec: dict[str, Any] = {"event": lab, "positioner": num, "kind": kind, "text": describe(lab)}
        if kind not in succ:
            rec.update(defined=False, why=_why_not(model, i, kind, pos, lvl))
            out.append(rec)
            break
        if not CONTROLLABLE[kind] or not pending:
            pass
        else:
            rec["preempted_by"] = [f"P{j}" for j in pending]
        p2, l2 = succ[kind]
        pos, lvl = pos[:i] + (p2,) + pos[i + 1:], lvl[:i] + (l2,) + lvl[i + 1:]
        rec.update(defined=True, pending_before=pending, position=list(pos), level=list(lvl),
                   zone={f"P{j + 1}": [f"P{x + 1}" for x in model.in_zone(j, pos)] for j in range(inst.size)})
        out.append(rec)
    return out


def _why_not(model: CoupledModel, i: int, kind: str, pos, lvl) -> str:
    c = len(model.in_zone(i, pos))
    if kind in ("v", "w") and lvl[i]:
        return f"P{i + 1} is in collision mode (level {lvl[i]}): only its priority move or a free event can follow"
    if kind in ("v", "w", "h", "l"):
        sign = 1 if kind in ("v", "h") else -1
        if not model.move_free(i, pos, sign):
            return "the move would hit a neighbour's arm"
        if kind in ("h", "l"):
            return f"P{i + 1}'s priority class among the {c} neighbour(s) in its zone does not allow {kind}"
    if kind == "k":
        return f"no new neighbour entered P{i + 1}'s safety zone ({c} inside, level {lvl[i]})"
    if kind == "e":
        return f"P{i + 1}'s zone is not empty ({c} inside) or nothing was registered"
    return f"{kind} is not defined for P{i + 1} here"


def replay_literal(inst: PaperInstance, labels: Sequence[str]) -> list[dict[str, Any]]:
    """Run ``labels`` in the literal ``G^P`` and ``S^P`` (each event moves its own positioner)."""
    from .literal import plant_explicit

    gs = [plant_explicit(i + 1, inst.steps, inst.start[i], inst.target[i], inst.priority_kind(i)) for i in range(inst.size)]
    ss = [spec_explicit(i + 1, inst.steps, inst.start[i], inst.target[i]) for i in range(inst.size)]
    gq = [g.init for g in gs]
    sq = [s.init for s in ss]
    out = []
    for lab in labels:
        num, kind = decode_label(lab)
        i = num - 1
        rec: dict[str, Any] = {"event": lab, "positioner": num, "kind": kind, "text": describe(lab)}
        d = gs[i].successor(gq[i], lab)
        ds = ss[i].successor(sq[i], lab) if lab in ss[i].events else sq[i]
        if d is None or ds is None:
            rec.update(defined=False, why="not defined in G^P" if d is None else "disabled by S^P")
            out.append(rec)
            break
        gq[i], sq[i] = d, ds
        rec.update(defined=True, plant=[g.state_label(q) for g, q in zip(gs, gq)],
                   spec=[s.state_label(q) for s, q in zip(ss, sq)])
        out.append(rec)
    marked = all(q in g.marked for g, q in zip(gs, gq)) and all(q in s.marked for s, q in zip(ss, sq))
    if out:
        out[-1]["marked"] = marked
    return out


# -- the demo -----------------------------------------------------------------------


@dataclass
class DemoResult:
    payload: dict[str, Any]
    text: str
    files: dict[str, str] = field(default_factory=dict)


def replay_in(V, labels: Sequence[str]) -> bool:
    """Whether ``labels`` is a string of the symbolic supervisor ``V`` from its initial
    state that ends in its marked state (an independent check of a witness)."""
    q = V.init
    for lab in labels:
        if lab not in V.events:
            return False
        q = V.post(q, lab)
        if q == V.ctx.false:
            return False
    return q != V.ctx.false and (q & ~V.marked) == V.ctx.false


def _size(stats: dict[str, Any]) -> dict[str, Any]:
    return {k: stats[k] for k in ("states", "transitions", "marked", "bdd_nodes") if k in stats}


def _reachable_count(G) -> int:
    return G.ctx.count(reachable(G), G.variables)


def run_demo(out: str | Path | None = "supcoord-demo", *, steps: int = EXAMPLE_STEPS,
             target: Sequence[int] = EXAMPLE_TARGET, geometry: Geometry | None = None, figure: bool = True) -> DemoResult:
    """Build and solve the example in both readings; write files into ``out`` (None: none)."""
    t0 = time.perf_counter()
    inst = paper_example(steps, target)
    if out is not None:  # fail before the work, not after it (the directory is made only to write)
        check_demo_dir(out)
    # literal reading
    ctx = Context()
    G, E = literal_models(inst, ctx)
    lit = supcon(G, E)
    lit_c = {sem: ccc(lit.supervisor, sem) for sem in ("preemptive", "standard")}
    literal = {
        "plant_states": _reachable_count(G),
        "supervisor": _size(lit.stats),
        "verdict": {sem: c.forcible for sem, c in lit_c.items()},
        "ccc": {sem: {"forcible": c.forcible, "rank": c.rank, "layers": c.layers, "witness": c.witness}
                for sem, c in lit_c.items()},
        "priority_events": {f"P{i + 1}": inst.priority_kind(i) for i in range(inst.size)},
        "paper_path": replay_literal(inst, PAPER_PATH),
    }
    # coupled reading
    model = CoupledModel(inst, geometry)
    model.check()
    ctx2 = Context()
    Gc, Ec = coupled_models(model, ctx2)
    cou = supcon(Gc, Ec)
    V = cou.supervisor
    cc = ccc(V, "preemptive")
    cs = ccc(V, "standard")
    steps_explained = replay_coupled(model, cc.witness)
    ends_marked = bool(steps_explained) and steps_explained[-1].get("position") == list(inst.target) and not any(
        steps_explained[-1].get("level", [1]))
    coupled = {
        "plant_states": _reachable_count(Gc),
        "supervisor": _size(cou.stats),
        "ccc": {"semantics": "preemptive", "forcible": cc.forcible, "rank": cc.rank, "layers": cc.layers,
                "witness": cc.witness},
        "standard": {"forcible": cs.forcible, "rank": cs.rank, "witness": cs.witness},
        "witness_explained": steps_explained,
        "witness_reaches_target": ends_marked if cc.witness else inst.start == inst.target,
        "witness_replays_in_V": replay_in(V, cc.witness) if cc.forcible else False,
        "paper_path": replay_coupled(model, PAPER_PATH),
    }
    payload: dict[str, Any] = {
        "status": "ok",
        "instance": {
            "positioners": inst.size, "steps": inst.steps, "start": list(inst.start), "target": list(inst.target),
            "priority": list(inst.priority), "layout": model.bases.round(3).tolist(),
            "geometry": {"pitch": model.geo.pitch, "arm": model.geo.arm, "buffer": model.geo.buffer, "zone": model.geo.zone},
        },
        "supervisor": coupled["supervisor"],
        "ccc": coupled["ccc"],
        "witness": cc.witness,
        "coupled": coupled,
        "literal": literal,
        "paper_path": list(PAPER_PATH),
    }
    files: dict[str, str] = {}
    if out is not None:
        files = _write_files(Path(out), inst, model, V, cc.witness, figure)
    payload["files"] = files
    payload["seconds"] = round(time.perf_counter() - t0, 3)
    return DemoResult(payload, report(payload), files)


#: the files the demo writes into its directory
DEMO_FILES = ("G.gen", "S.gen", "V.gen", "demo.png")


def check_demo_dir(out: str | Path) -> Path:
    """Refuse, before any work, an output directory the demo could not fill: a file or a
    link where the directory should be, an unwritable directory, or one of the demo's file
    names taken by a directory or a non-regular file (one-line :class:`InputError`)."""
    out = Path(out)
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise InputError("is not a directory (the demo writes G.gen, S.gen, V.gen and demo.png into one)",
                         value=str(out), where=str(out))
    if out.exists():
        if not os.access(out, os.W_OK | os.X_OK):
            raise InputError("output directory is not writable", value=str(out), where=str(out))
        for name in DEMO_FILES:
            check_output(out / name, what="out")
        return out
    parent = out.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"cannot create the output directory: {parent} is not a writable directory",
                         value=str(out), where=str(out))
    return out


def _write_files(out: Path, inst: PaperInstance, model: CoupledModel, V, witness, figure: bool) -> dict[str, str]:
    """Write the demo's files; an error or an interrupt removes what this call created
    (the files it wrote and the directory if it made it), so nothing half-written stays."""
    from ..des.io import write_generator

    created = [p for p in (out, *out.parents) if not p.exists()]
    written: list[Path] = []
    try:
        out.mkdir(parents=True, exist_ok=True)
        G = plant_explicit(model)
        specs = [spec_explicit(i + 1, inst.steps, inst.start[i], inst.target[i], sees_priority=True,
                               absorbing=False) for i in range(inst.size)]
        S = XO.sync(*specs, name="S")
        Vx = to_explicit(V, name="V")
        files = {}
        for name, g in (("G", G), ("S", S), ("V", Vx)):
            path = out / f"{name}.gen"
            written.append(path)
            write_generator(g, path)
            files[name] = str(path)
        if figure:
            path = out / "demo.png"
            written.append(path)
            draw_demo(model, witness, path)
            files["figure"] = str(path)
        return files
    except BaseException as exc:
        for path in written:
            with contextlib.suppress(OSError):
                path.unlink()
        for path in created:  # innermost first
            with contextlib.suppress(OSError):
                path.rmdir()
        if isinstance(exc, OSError):
            raise InputError(f"cannot write the demo's files: {exc.strerror or exc}", value=str(out),
                             where=str(exc.filename or out)) from None
        raise


def draw_demo(model: CoupledModel, witness: Sequence[str], path: str | Path) -> None:
    """Layout, patrol circles, arms at start (solid) and target (dashed), the fibre tips
    along the witness (numbered ``#k``: the k-th event of the witness moved that arm
    there) and the witness itself, event by event, beside the plot — matplotlib Agg."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    inst, geo = model.inst, model.geo
    steps = replay_coupled(model, witness)
    configs = [list(inst.start)] + [r["position"] for r in steps if r.get("defined")]
    fig, ax = plt.subplots(figsize=(10.5, 6.0))
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]

    tip = model.fibre
    for i in range(inst.size):
        col = colours[i % len(colours)]
        b = model.bases[i]
        ax.add_patch(plt.Circle(b, geo.arm, fill=False, ls=":", color="0.7"))
        for q in range(inst.steps):  # the n discrete positions of the fibre tip
            ax.plot(*tip(i, q), ".", color="0.75", ms=3)
        s, t = tip(i, inst.start[i]), tip(i, inst.target[i])
        ax.plot([b[0], s[0]], [b[1], s[1]], "-", color=col, lw=3, label=f"P{i + 1}: start position {inst.start[i]}")
        ax.plot([b[0], t[0]], [b[1], t[1]], "--", color=col, lw=2, label=f"P{i + 1}: target position {inst.target[i]}")
        ax.plot(*b, "o", color=col, ms=8)
        ax.annotate(f"P{i + 1}", b, textcoords="offset points", xytext=(-14, -14))
        trail = [tip(i, c[i]) for c in configs]
        xs, ys = zip(*trail)
        ax.plot(xs, ys, "-", color=col, alpha=0.4)
    for k, (prev, cur) in enumerate(zip(configs, configs[1:]), 1):
        for i in range(inst.size):
            if prev[i] != cur[i]:
                t = tip(i, cur[i])
                ax.annotate(f"#{k}", t, fontsize=8, fontweight="bold", color=colours[i % len(colours)],
                            textcoords="offset points", xytext=(4, 4))
                ax.plot(*t, "o", color=colours[i % len(colours)], ms=5)
    handles, labels = ax.get_legend_handles_labels()
    handles.append(Line2D([], [], ls="", marker="o", color="0.3", ms=5))
    labels.append("#k at a fibre tip: the k-th event of\nthe forcing path moved the arm there")
    handles.append(Line2D([], [], ls="", marker=".", color="0.6", ms=6))
    labels.append(f"the {inst.steps} positions of a tip: position k\nat angle -360°·k/{inst.steps} from +x "
                  "(v: k+1, clockwise)")
    ax.legend(handles, labels, fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    lines = [f"forcing path (preemptive CCC), {len(witness)} events:"]
    for k, r in enumerate(steps, 1):
        lines.append(f"#{k} {r['event']:>3}  P{r['positioner']} {r['kind']}: {_SHORT[r['kind']]}")
    ax.text(1.02, 0.38, "\n".join(lines), transform=ax.transAxes, fontsize=7, va="top", family="monospace")
    ax.set_aspect("equal")
    ax.set_title(f"supcoord demo: the paper's example, coupled reading (n = {inst.steps} positions per arm, "
                 f"safety zone {geo.zone:g} mm)", fontsize=9)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    fig.tight_layout()
    try:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, dpi=110, format="png")
    finally:
        plt.close(fig)
