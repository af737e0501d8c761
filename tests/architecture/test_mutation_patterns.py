"""Every curated mutation of ``benchmarks/mutations.py`` still applies to today's source.

A mutation replaces one exact piece of source text; when a refactoring moves or rewrites
that text, the mutation no longer applies and the script reports it only when run (it is a
benchmark, not a test). This test reads the same list and fails as soon as a pattern no
longer occurs exactly once in its file, or a test file it runs is gone, so a refactoring
cannot silently disable a mutation.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _mutations() -> list:
    spec = importlib.util.spec_from_file_location("curated_mutations", ROOT / "benchmarks" / "mutations.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up while it runs
    spec.loader.exec_module(module)
    return module.MUTATIONS


MUTATIONS = _mutations()


def test_the_mutation_ids_are_unique():
    ids = [m.id for m in MUTATIONS]
    assert len(ids) == len(set(ids)) and len(ids) >= 20


@pytest.mark.parametrize("mutation", MUTATIONS, ids=lambda m: m.id)
def test_a_curated_mutation_applies_to_the_source(mutation):
    path = ROOT / "src" / "supcoord" / mutation.path
    assert path.exists(), f"{mutation.id}: {mutation.path} is gone"
    count = path.read_text().count(mutation.old)
    assert count == 1, f"{mutation.id}: its pattern occurs {count} times in {mutation.path}, not once"
    assert mutation.new != mutation.old
    missing = [t for t in mutation.tests if not (ROOT / t).exists()]
    assert mutation.tests and not missing, f"{mutation.id}: test files gone: {missing}"
