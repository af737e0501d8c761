"""``supcoord force``: the formats.md JSON, exit statuses, .gen files written by
libFAUDES itself, and agreement with the explicit twin on random generators."""

import json
import re

import faudes
import pytest

from supcoord.cli.main import main
from supcoord.des.generator import Event, Generator
from supcoord.des.io import write_generator
from supcoord.synthesis import forcible_layers_naive
from supcoord.synthesis.forcibility import rank_naive
from supcoord.synthesis.witness import witness_naive


def faudes_write(g: Generator, path, names=False):
    """Write ``g`` with libFAUDES (states by index 1..n, or named ``s<q>``)."""
    f = faudes.System()
    f.Name(g.name)
    idx = [f.InsState(f"s{q}") if names else f.InsState() for q in range(g.n_states)]
    ev = {}
    for e in g.alphabet:
        ev[e.name] = f.InsEvent(e.name)
        if e.controllable:
            f.SetControllable(e.name)
    for s, e, d in g.transitions():
        f.SetTransition(idx[s], ev[e], idx[d])
    if g.init is not None:
        f.SetInitState(idx[g.init])
    for q in g.marked:
        f.SetMarkedState(idx[q])
    f.Write(str(path))


def run_cli(capsys, *argv):
    code = main(["force", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def chain():
    ev = [Event("a", True), Event("u", False)]
    return Generator(4, ev, [(0, "a", 1), (1, "u", 2), (2, "a", 3)], 0, [3], "chain")


@pytest.mark.parametrize("names", [False, True])
def test_force_reads_libfaudes_files(tmp_path, capsys, names):
    path = tmp_path / "V.gen"
    faudes_write(chain(), path, names)
    code, out, _ = run_cli(capsys, path, "--json")
    assert code == 0
    got = json.loads(out)
    effort = got.pop("effort")
    assert got == {"status": "ok", "forcible": True, "witness": ["a", "u", "a"], "rank": 3, "layers": [1, 1, 1, 1]}
    assert set(effort["stage_seconds"]) == {"ccc"} and effort["cudd_lookups"] > 0 and effort["peak_live_nodes"] > 0
    for target in (["s2", "3"] if names else ["3"]):  # by name, or the libFAUDES index
        code, out, _ = run_cli(capsys, path, "--json", "--target", target)
        assert code == 0 and json.loads(out)["witness"] == ["a", "u"]
    code, out, _ = run_cli(capsys, path, "--json", "--semantics", "standard")
    assert json.loads(out) | {"effort": None} == {"status": "ok", "forcible": False, "witness": [], "rank": None,
                                                  "layers": [1, 1], "effort": None}
    code, out, _ = run_cli(capsys, path)
    assert code == 0 and "FORCIBLE" in out and "a u a" in out


def test_force_json_state_numbers_and_errors(tmp_path, capsys):
    path = tmp_path / "V.json"
    write_generator(chain(), path)
    code, out, _ = run_cli(capsys, path, "--json", "--target", "2")
    assert code == 0 and json.loads(out)["witness"] == ["a", "u"]
    code, out, err = run_cli(capsys, path, "--json", "--target", "7")
    assert code == 2 and out == "" and err.count("\n") == 1 and "unknown state '7'" in err
    code, out, err = run_cli(capsys, path, "--target", "nowhere")
    assert code == 2 and "nowhere" in err
    code, out, err = run_cli(capsys, tmp_path / "missing.gen")
    assert code == 2 and err.count("\n") == 1 and "missing.gen" in err
    bad = tmp_path / "bad.gen"
    bad.write_text("<Generator> oops")
    code, out, err = run_cli(capsys, bad)
    assert code == 2 and err.count("\n") == 1


def test_force_budget_exit_3(tmp_path, capsys):
    path = tmp_path / "V.gen"
    write_generator(chain(), path)
    code, out, _ = run_cli(capsys, path, "--json", "--max-nodes", "1")
    assert code == 3 and json.loads(out)["status"] == "unknown"


def test_force_empty_generator(tmp_path, capsys):
    path = tmp_path / "E.json"
    write_generator(Generator(0, [Event("a", True)], []), path)
    code, out, _ = run_cli(capsys, path, "--json")
    assert code == 0 and json.loads(out) | {"effort": None} == {"status": "ok", "forcible": False, "witness": [],
                                                                "rank": None, "layers": [0], "effort": None}


def test_force_cli_random_payloads(tmp_path, capsys):
    """Random generators written by libFAUDES: the JSON equals the explicit twin's answer
    (a seeded sample: hypothesis and the function-scoped capsys fixture do not mix)."""
    import random

    rng = random.Random(7)
    for i in range(40):
        n = rng.randint(1, 6)
        ev = [Event(x, rng.random() < 0.5) for x in "abcd"]
        t = [(q, e.name, rng.randrange(n)) for q in range(n) for e in ev if rng.random() < 0.5]
        g = Generator(n, ev, t, 0, rng.sample(range(n), rng.randint(0, n)), f"R{i}")
        path = tmp_path / f"R{i}.gen"
        faudes_write(g, path)
        for semantics in ("preemptive", "standard"):
            code, out, _ = run_cli(capsys, path, "--json", "--semantics", semantics)
            got = json.loads(out)
            naive = forcible_layers_naive(g, g.marked, semantics)
            assert code == 0
            assert got["layers"] == [len(x) for x in naive]
            assert got["rank"] == rank_naive(naive, 0)
            assert got["forcible"] == (got["rank"] is not None)
            assert got["witness"] == (witness_naive(g, naive, 0, semantics) or [])


def _state_indices(text: str) -> list[int]:
    """The state indices of a ``.gen`` file's ``<States>`` section, ``<Consecutive> a b
    </Consecutive>`` ranges expanded (how libFAUDES may write runs without gaps)."""
    section = re.search(r"<States>(.*?)</States>", text, re.DOTALL).group(1)
    out: list[int] = []
    for lo, hi, single in re.findall(r"<Consecutive>\s*(\d+)\s+(\d+)\s*</Consecutive>|(\d+)", section):
        out.extend(range(int(lo), int(hi) + 1) if lo else [int(single)])
    return out


def test_state_indices_reads_consecutive_ranges():
    assert _state_indices("<States>\n<Consecutive> 1 3 </Consecutive> 7\n</States>") == [1, 2, 3, 7]


def test_force_target_by_libfaudes_index_in_a_file_with_gaps(tmp_path, capsys):
    """libFAUDES keeps index gaps after deleting states: ``--target 5`` is the state
    with index 5 (the third one in the file), not the fifth state."""
    f = faudes.System()
    a = f.InsControllableEvent("a")
    states = [f.InsState() for _ in range(6)]  # indices 1..6
    f.DelState(states[2])
    f.DelState(states[3])  # left: 1, 2, 5, 6
    for x, y in [(1, 2), (2, 5), (5, 6)]:
        f.SetTransition(x, a, y)
    f.SetInitState(1)
    f.SetMarkedState(6)
    path = tmp_path / "gaps.gen"
    f.Write(str(path))
    assert _state_indices(path.read_text()) == [1, 2, 5, 6]  # the file keeps the gaps
    code, out, _ = run_cli(capsys, path, "--json", "--target", "5")
    assert code == 0 and json.loads(out)["witness"] == ["a", "a"]
    code, out, _ = run_cli(capsys, path, "--json", "--target", "6")
    assert code == 0 and json.loads(out)["rank"] == 3
    code, _, err = run_cli(capsys, path, "--json", "--target", "3")  # deleted: a user error
    assert code == 2 and "'3'" in err
