"""Scalable families: small sizes agree with libFAUDES, closed forms hold, and the
symbolic supcon agrees with both."""

from __future__ import annotations

import pytest
from faudes_twin import faudes_supcon, symbolic_supcon

from supcoord.des import families
from supcoord.errors import InputError

CASES = [
    ("dining_philosophers", 2), ("dining_philosophers", 3), ("dining_philosophers", 5),
    ("small_factories", 2), ("coupled_factories", 2), ("coupled_factories", 3),
    ("transfer_line_chain", 1), ("transfer_line_chain", 2),
    ("machine_line", 3), ("machine_line", 4),
]


@pytest.mark.parametrize("family,size", CASES)
def test_family_agrees_with_libfaudes(family, size, tmp_path):
    plants, specs = families.FAMILIES[family](size)
    expected = faudes_supcon(plants, specs, tmp_path)
    st = symbolic_supcon(plants, specs)
    assert (st["states"], st["transitions"]) == expected


@pytest.mark.parametrize("n", [2, 3, 4, 6])
def test_dining_philosophers_closed_form(n):
    st = symbolic_supcon(*families.dining_philosophers(n))
    assert st["states"] == 3**n - 2


@pytest.mark.parametrize("k", [1, 2, 3])
def test_independent_small_factories_closed_form(k):
    st = symbolic_supcon(*families.small_factories(k))
    assert (st["states"], st["transitions"]) == (12**k, 24 * k * 12 ** (k - 1))


def test_transfer_line_chain_of_one_is_the_classic_model():
    st = symbolic_supcon(*families.transfer_line_chain(1))
    assert (st["states"], st["transitions"]) == (28, 65)


def test_declaration_order_interleaves_buffers():
    plants, specs = families.machine_line(3)
    order = families.declaration_order(plants, specs)
    assert order == [("plant", 0), ("plant", 1), ("spec", 0), ("plant", 2), ("spec", 1)]


def test_components_stay_small_and_bad_sizes_raise():
    for family in families.FAMILIES:
        plants, specs = families.FAMILIES[family](3)
        assert all(g.n_states <= 4 for g in plants + specs)
    for bad in (0, -1, 1.5, True):
        with pytest.raises(InputError):
            families.machine_line(bad)
