"""Old import paths keep working for one release, each with a DeprecationWarning naming the new home."""

from __future__ import annotations

import importlib
import json
import sys
import warnings
from pathlib import Path

import pytest

import supcoord
from supcoord._compat import MOVED, POSITIONERS_NAMES, REMOVED

#: every moved module's ``__all__`` in release 0.1 (read from that release's source)
API_0_1: dict[str, list[str]] = json.loads((Path(__file__).resolve().parents[1] / "data" / "api_0_1_moved_modules.json").read_text())

OLD_POSITIONERS_ALL = [  # supcoord.positioners.__all__ of release 0.1
    "hex_count", "hex_grid", "layout_from_spec", "points_layout", "AlphaBeta", "Joint", "Kinematics", "Rotary",
    "kinematics_from_spec", "CollisionTables", "colliding_pairs", "motion_collides", "neighbour_pairs",
    "segment_distance", "simultaneous_table", "static_table", "swept_table", "Problem", "load_problem",
    "parse_problem", "Plan", "compact_moves", "event_name", "load_plan", "lower_bound", "parse_event",
    "parse_plan", "plan_from_moves", "validate_plan", "random_configuration", "random_problem", "PRESETS",
    "Preset", "preset_problem", "CoordinationModel", "conflict_components", "rcm_order", "solve",
    "bfs_plan_naive", "optimal_makespan_naive",
]


def _fresh_import(name: str):
    """Import ``name`` as a user would the first time, recording the warnings."""
    for key in [k for k in sys.modules if k == name or k.startswith(name + ".")]:
        if key.startswith(("supcoord.positioners", "supcoord.symbolic")) or key[len("supcoord."):] in MOVED:
            del sys.modules[key]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(name)
    return module, [w for w in caught if issubclass(w.category, DeprecationWarning)]


@pytest.mark.parametrize("old", sorted(MOVED))
def test_every_old_module_path_imports_with_a_warning_and_forwards(old):
    module, caught = _fresh_import("supcoord." + old)
    assert caught, f"no DeprecationWarning for supcoord.{old}"
    new = "supcoord." + MOVED[old]
    assert new in str(caught[-1].message)
    target = importlib.import_module(new)
    for name in getattr(target, "__all__", []):
        assert getattr(module, name) is getattr(target, name), f"supcoord.{old}.{name}"
    missing = [n for n in API_0_1[old] if n not in REMOVED.get(old, ()) and not hasattr(module, n)]
    assert not missing, f"supcoord.{old} lost names of release 0.1: {missing}"


def test_every_moved_module_of_release_0_1_has_an_alias():
    assert set(API_0_1) - {"positioners", "symbolic"} == set(MOVED) - {"symbolic"}


def test_the_old_positioners_package_still_has_every_name():
    assert sorted(POSITIONERS_NAMES) == sorted(OLD_POSITIONERS_ALL)
    module, caught = _fresh_import("supcoord.positioners")
    assert caught and "supcoord.geometry" in str(caught[0].message)
    for name in OLD_POSITIONERS_ALL:
        assert getattr(module, name) is getattr(importlib.import_module("supcoord." + POSITIONERS_NAMES[name]), name)
    # supcoord.solve is the same function behind the public boundary's argument checks
    assert module.solve is supcoord.solve.__wrapped__ and module.Plan is supcoord.Plan


def test_from_old_package_import_a_submodule():
    _fresh_import("supcoord.positioners")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from supcoord.positioners import planner  # noqa: F401  (a module, as `from package import module`)
        from supcoord.symbolic import Context
    assert planner.solve is supcoord.solve.__wrapped__
    assert Context is supcoord.Context


def test_an_unknown_old_name_is_an_attribute_error():
    module, _ = _fresh_import("supcoord.positioners")
    with pytest.raises(AttributeError):
        module.no_such_thing  # noqa: B018


def test_new_paths_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        for name in ("supcoord.planning", "supcoord.problems", "supcoord.geometry", "supcoord.paper", "supcoord.bdd",
                     "supcoord.des.io", "supcoord.testing"):
            importlib.import_module(name)
