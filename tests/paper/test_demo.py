"""``supcoord demo``: the paper's example end to end, its files checked by libFAUDES."""

from __future__ import annotations

import json

import faudes
import pytest
from oracle import faudes_is_controllable, faudes_is_nonblocking

from supcoord.cli.main import main
from supcoord.des.io import read_generator
from supcoord.paper.demo import PAPER_PATH, run_demo


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    return run_demo(out), out


def test_payload_has_the_issue_keys(demo):
    result, _ = demo
    p = result.payload
    assert {"states", "transitions", "marked"} <= set(p["supervisor"])
    assert p["supervisor"]["marked"] == 1
    assert p["ccc"]["forcible"] and p["ccc"]["semantics"] == "preemptive"
    assert p["witness"] == p["ccc"]["witness"] == ["10", "20", "15", "50", "83", "93"]
    assert p["coupled"]["witness_replays_in_V"] and p["coupled"]["witness_reaches_target"]
    lit = p["literal"]
    assert {"states", "transitions", "marked"} <= set(lit["supervisor"]) and lit["supervisor"]["marked"] == 1
    assert lit["verdict"] == {"preemptive": False, "standard": False}
    assert p["paper_path"] == list(PAPER_PATH)
    json.dumps(p)  # plain JSON


def test_files_are_what_libfaudes_reads_and_confirms(demo):
    """V.gen is controllable for G.gen and nonblocking with one marked state (the paper's
    Theorem (i)), and the witness replays in V.gen to that state."""
    result, out = demo
    assert set(result.files) == {"G", "S", "V", "figure"}
    G, V = read_generator(out / "G.gen"), read_generator(out / "V.gen")
    assert faudes.Generator(str(out / "V.gen")).Size() == V.n_states == result.payload["supervisor"]["states"]
    assert faudes_is_controllable(G, V) and faudes_is_nonblocking(V)
    assert len(V.marked) == 1 and V.run(result.payload["witness"]) in V.marked
    assert (out / "demo.png").stat().st_size > 10_000


def test_report_explains_both_readings_and_the_papers_path(demo):
    text = demo[0].text
    for needle in ("Literal reading", "Coupled reading", "NOT forcible", "shortest forcing path: <10, 20, 15, 50, 83, 93>",
                   "The paper's path <73, 10, 30, 15, 31, 81, 20>", "ends in V's marked state: True"):
        assert needle in text, needle


def test_unwritable_output_directory_is_one_line(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["demo", "--out", str(blocker / "sub")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "sub" in err[0]
