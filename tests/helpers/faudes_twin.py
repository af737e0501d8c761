"""Supervisors computed twice: by libFAUDES (the independent oracle) and by supcoord's symbolic
``supcon``, on the same plant and specification components."""

from __future__ import annotations

import faudes

from supcoord.bdd import Context
from supcoord.des import families, symbolic_ops
from supcoord.des.generator import Generator
from supcoord.des.io.gen_file import format_gen
from supcoord.synthesis import lift_spec, supcon


def to_faudes(g: Generator, tmp_path) -> faudes.System:
    path = tmp_path / f"{g.name}.gen"
    path.write_text(format_gen(g), encoding="latin-1")
    return faudes.System(str(path))


def faudes_supcon(plants: list[Generator], specs: list[Generator], tmp_path) -> tuple[int, int]:
    """libFAUDES: Parallel the components, InvProject the spec to the plant alphabet, SupCon."""
    P = to_faudes(plants[0], tmp_path)
    for g in plants[1:]:
        out = faudes.System()
        faudes.Parallel(P, to_faudes(g, tmp_path), out)
        P = out
    if specs:
        S = to_faudes(specs[0], tmp_path)
        for g in specs[1:]:
            out = faudes.System()
            faudes.Parallel(S, to_faudes(g, tmp_path), out)
            S = out
        faudes.InvProject(S, P.Alphabet())
    else:  # allevents(plant)
        S = faudes.System()
        S.InsEvents(P.Alphabet())
        q = S.InsState()
        S.SetInitState(q)
        S.SetMarkedState(q)
        for e in P.Alphabet():
            S.SetTransition(q, e, q)
    R = faudes.System()
    faudes.SupCon(P, S, R)
    # every published supervisor is nonempty: an empty R would make the check below vacuous
    assert R.Size() > 0, "libFAUDES found no supervisor"
    assert faudes.IsControllable(P, R)
    return R.Size(), R.TransRelSize()


def symbolic_supcon(plants: list[Generator], specs: list[Generator]) -> dict:
    ctx = Context()
    G, E = families.to_symbolic(ctx, plants, specs)
    E = lift_spec(G, E) if E is not None else symbolic_ops.allevents(ctx, G)
    return supcon(G, E).stats
