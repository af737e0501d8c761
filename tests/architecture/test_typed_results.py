"""Typed results are read by attribute only: no dictionary call form (``result["valid"]``)
on the result dataclasses, and their JSON made in one place, their ``to_json``."""

import dataclasses

import pytest

from supcoord.geometry.collision import TableStatistics
from supcoord.planning.improve import ImproveStats
from supcoord.planning.optimum import MakespanResult
from supcoord.planning.search import SearchStats
from supcoord.problems.validation_result import Incident, ValidationResult

RESULTS = [ValidationResult, Incident, ImproveStats, MakespanResult, SearchStats, TableStatistics]
DICT_METHODS = ["__getitem__", "get", "keys", "items", "values", "__contains__", "__iter__"]


@pytest.mark.parametrize("cls", RESULTS, ids=lambda c: c.__name__)
def test_results_are_frozen_dataclasses_without_a_dictionary_call_form(cls):
    assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen
    assert [m for m in DICT_METHODS if hasattr(cls, m)] == []


def test_search_statistics_give_the_json_the_error_values_carried():
    assert SearchStats(2, 1, 0.5).to_json() == {"forward": 2, "backward": 1, "seconds": 0.5}


def test_a_result_refuses_a_subscript_and_its_json_is_made_from_its_fields():
    inc = Incident(step=3, positioners=[0, 4], t=0.25, distance=1.5, required=2.0)
    r = ValidationResult(False, 1, 1, ["step 3->4: positioners 0 and 4 collide"], 5, -0.5, [inc])
    with pytest.raises(TypeError):
        r["valid"]  # noqa: B018 (the subscript is the test)
    with pytest.raises(TypeError):
        inc["step"]  # noqa: B018
    assert r.to_json()["incidents"] == [{"step": 3, "positioners": [0, 4], "t": 0.25, "distance": 1.5,
                                         "required": 2.0}]
    against = dataclasses.replace(inc, positioners=[0], obstacle=2).to_json()
    assert list(against) == ["step", "positioners", "t", "distance", "required", "obstacle"]
    assert against["obstacle"] == 2
