"""``supcoord.bdd.BDD``, the one type of a BDD node: each backend's nodes have its members,
and the public boundary leaves BDD arguments to the functions (as it did with ``Any``)."""

from __future__ import annotations

import importlib

import pytest

from supcoord._boundary import _check_for
from supcoord.bdd.backend import BDD
from supcoord.bdd import counting

def _protocol_members() -> list[str]:
    own = [n for n in vars(BDD) if not n.startswith("_") or n in
           ("__invert__", "__and__", "__or__", "__eq__", "__hash__", "__int__")]
    return sorted(n for n in own if n not in ("_is_protocol", "_is_runtime_protocol"))


@pytest.mark.parametrize("backend", ["dd.autoref", "dd.cudd"])
def test_every_backend_node_has_the_members_of_bdd(backend):
    dd = pytest.importorskip(backend)
    manager = dd.BDD()
    manager.declare("x", "y")
    nodes = [manager.var("x") & ~manager.var("y"), manager.true, manager.false]
    members = _protocol_members()
    assert {"var", "low", "high", "negated", "level", "support", "__and__"} <= set(members)
    for u in nodes:
        missing = [m for m in members if not hasattr(u, m)]
        assert not missing, f"{backend} node lacks {missing}"


def test_counting_and_the_backend_name_one_type():
    assert counting.BDD is BDD
    assert importlib.import_module("supcoord.bdd.context").BDD is BDD


def test_bdd_arguments_are_not_checked_at_the_public_boundary():
    assert _check_for(BDD) is None
    assert _check_for(BDD | None) is None
