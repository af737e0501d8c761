"""The planner's front door: ``solve`` runs the route its options name, reports it, keeps the
statistics typed and writes them in the order the run reached them; the command line maps its
flags to the routes' options."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from supcoord.cli.main import main
from supcoord.errors import InputError, ModelError
from supcoord.planning import FinerLattice, Local, Monolithic, Simultaneous, solve
from supcoord.planning.routes import LocalRoute, MonolithicRoute, route_named, route_runner
from supcoord.planning.solve_stats import DescentShort, MonolithicStats, Recorded, SolveStats, WindowStats
from supcoord.planning.windows import WindowObserver
from supcoord.problems.problem import load_problem

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"


@pytest.fixture(scope="module")
def three():
    return load_problem(EXAMPLES / "three_rotary.json")


def test_each_route_runs_and_is_reported(three):
    local = solve(three, Local(), improve=0)
    mono = solve(three, Monolithic(), improve=0)
    assert local.stats["route"] == "local" and local.stats["order"] == "rcm"
    assert "components" in local.stats and "supervisor_states" not in local.stats  # the windows ran
    assert mono.stats["route"] == "monolithic" and mono.stats["order"] == "hex"
    assert mono.stats["windows"] == 1 and mono.stats["supervisor_states"] > 0  # supcon ran
    assert "components" not in mono.stats
    assert local.stats["single_moves"] == mono.stats["single_moves"] == 18  # both shortest
    search = solve(three, Monolithic(fixpoint="search", order="rcm"), improve=0)
    assert search.stats["order"] == "rcm" and "supervisor_states" not in search.stats
    assert solve(three, "monolithic", improve=0).stats["route"] == "monolithic"  # a name: its defaults


def test_the_runner_is_the_one_of_the_options_type(three):
    def new_model(problem, order):
        return order  # no model is needed to see which runner is built

    assert isinstance(route_runner(three, Local(), new_model), LocalRoute)
    assert isinstance(route_runner(three, Monolithic(), new_model), MonolithicRoute)
    assert route_named("monolithic", "rcm") == Monolithic(order="rcm")
    assert route_named("local") == Local()


@pytest.mark.parametrize("call", [
    lambda p: solve(p, "nope"),
    lambda p: solve(p, route=3),
    lambda p: solve(p, Monolithic(fixpoint="nope")),
    lambda p: solve(p, Local(descent="nope")),
    lambda p: solve(p, simultaneous=True),
    lambda p: solve(p, finer=False),
    lambda p: solve(p, validation="maybe"),
    lambda p: solve(p, improve=-1),
])
def test_bad_options_are_input_errors(three, call):
    with pytest.raises(InputError):
        call(three)


def test_the_last_window_level_must_be_uncapped(three):
    with pytest.raises(ModelError):
        solve(three, Local(levels=(10, 100)))


class _Watch(WindowObserver):
    def __init__(self):
        self.seen = []

    def descended(self, steps):
        self.seen.append("descent")

    def window(self, outcome):
        self.seen.append(f"window {outcome.kind}")

    def whole_component(self, outcome):
        self.seen.append(f"whole {outcome.kind}")


def test_the_observer_watches_without_changing_the_plan(three):
    plain = solve(three, Local(), improve=0)
    watch = _Watch()
    watched = solve(three, Local(observer=watch), improve=0)
    assert watch.seen[:2] == ["descent", "descent"]  # the two directions' descents
    assert "whole solved" in watch.seen  # three robots in one small component: one exact window
    assert watched.events == plain.events and watched.stats["windows"] == plain.stats["windows"]
    forced = _Watch()
    solve(three, Local(small_component=0, descent="none", observer=forced), improve=0)
    assert forced.seen and "descent" not in forced.seen and not any(s.startswith("whole") for s in forced.seen)
    assert "window solved" in forced.seen


def test_statistics_are_written_in_the_order_first_set():
    stats = SolveStats()
    stats.route, stats.order, stats.positioners = "local", "rcm", 2
    stats.descent_short = DescentShort(1, 0)
    stats.search = own = WindowStats()
    own.begin(1, 2, 0)
    own.count_solved(2)
    own.windows_few_displaced += 1
    own.window_peak_nodes = 7
    stats.seconds = 1.0
    stats.certificate = [0, 1]
    stats.seconds = 2.0  # a later value keeps its place
    out = stats.to_json()
    assert list(out) == ["route", "order", "positioners", "descent_short", "components", "largest_component",
                         "windows", "largest_window", "window_sizes", "relaxed_checks", "windows_abandoned",
                         "descent_steps", "descent_moves", "at_target", "windows_few_displaced", "window_peak_nodes",
                         "seconds", "certificate"]
    assert out["seconds"] == 2.0 and out["descent_short"] == {"forward": 1, "reverse": 0}
    assert out["window_sizes"] == {"2": 1} and stats.window_peak_nodes() == 7
    mono = MonolithicStats()
    mono.single_moves = None  # set, even to None: written (an infeasible window has no rank)
    assert mono.to_json() == {"single_moves": None}
    assert isinstance(mono, Recorded) and SolveStats().to_json() == {}


def test_the_command_line_maps_its_flags_to_the_routes_options(capsys):
    triangle = str(EXAMPLES / "infeasible_triangle.json")
    assert main(["solve", triangle, "--json", "--single-move-only", "--route", "monolithic", "--order", "rcm",
                 "--require-all"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "infeasible" and out["stats"]["route"] == "monolithic"
    assert out["stats"]["order"] == "rcm" and out["stats"]["certificate_model"] == "single-move"
    assert out["reason"].endswith("moves of several joints at once: not searched (simultaneous=False)")
    assert solve(load_problem(triangle), simultaneous=Simultaneous(), finer=FinerLattice()).stats[
        "certificate_model"] == "simultaneous"  # the default: searched with simultaneous moves too
