"""What ``trim`` and ``event_clusters`` hand back besides the fixpoint itself: the name the
caller gave the trimmed generator, and the clusters of the events the caller asked about."""

from __future__ import annotations

import pytest

from supcoord.bdd import Context
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import METHODS, event_clusters, trim


def _counters(k: int):
    ctx = Context()
    gens = []
    for i in range(k):
        up, down = Event(f"up{i}", i % 2 == 0), Event(f"down{i}", True)
        trans = [(0, up.name, 1), (1, up.name, 2), (2, down.name, 1), (2, up.name, 3)]  # 3: blocking
        g = Generator(4, [up, down], trans, 0, [1], f"C{i}")
        gens.append(from_explicit(ctx, g))
    return S.sync(*gens)


@pytest.mark.parametrize("method", METHODS)
def test_trim_names_its_result_as_asked(method):
    G = _counters(2)
    T = trim(G, "kept", method=method)
    assert T.name == "kept"
    assert T.count_states() == 3 * 3


@pytest.mark.parametrize("subset", [["up1"], ["down0", "up2"], ["up0", "down1", "down2"]])
def test_event_clusters_of_some_events_hold_those_events_only(subset):
    G = _counters(3)
    clusters = event_clusters(G, subset)
    assert sorted(e for c in clusters for e in c) == sorted(subset)
    everything = event_clusters(G)
    assert sorted(e for c in everything for e in c) == sorted(G.events)
