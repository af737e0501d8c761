"""Results and docs are read on other machines: none names a directory of the machine that wrote it."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: an absolute path into a machine's own directories (not part of a URL or a longer path)
MACHINE_PATH = re.compile(rb"(?<![\w.~-])/(?:work|tmp|root|home)/")


def _files() -> list[Path]:
    found = [ROOT / "README.md"]
    for folder in (ROOT / "benchmarks" / "results", ROOT / "docs"):
        found += [p for p in folder.rglob("*") if p.is_file()]
    return found


def test_no_results_file_or_doc_names_a_machine_path():
    files = _files()
    assert len(files) > 50 and any(p.suffix == ".sqlite" for p in files)
    hits = []
    for path in files:
        data = path.read_bytes()
        for m in MACHINE_PATH.finditer(data):
            hits.append(f"{path.relative_to(ROOT)}: ...{data[max(0, m.start() - 40):m.end() + 40]!r}...")
    assert not hits, "machine paths:\n" + "\n".join(hits[:20])


def test_the_pattern_finds_machine_paths_and_spares_urls():
    assert MACHINE_PATH.search(b"--work /tmp/vsk_apo2 --out x")
    assert MACHINE_PATH.search(b'"/work/kaiju-venv/bin/python"')
    assert not MACHINE_PATH.search(b"https://example.org/home/page and $WORK/a.json")


def test_the_kaiju_comparison_records_commands_without_machine_paths():
    spec = importlib.util.spec_from_file_location("vs_kaiju", ROOT / "benchmarks" / "vs_kaiju.py")
    vs_kaiju = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(vs_kaiju)

    class Args:
        work, instances, reuse = "/tmp/vsk_apo2", "/tmp/kaiju_instances", "/tmp/kaiju_meas"
        kaiju_python, supcoord = "/work/kaiju-venv/bin/python", "/work/main/.venv/bin/supcoord"

    places = vs_kaiju.run_places(Args)
    cmd = ["nice", Args.supcoord, "solve", "/tmp/vsk_apo2/apo_s0_fold_13x7.problem.json", "--out=/tmp/bk/x.json",
           "--instances", Args.instances, Args.kaiju_python, str(ROOT / "benchmarks" / "kaiju_side.py"),
           "/tmp/kaiju_meas/apo_s0_mdp_fold.json"]
    line = " ".join(vs_kaiju.portable(c, places) for c in cmd)
    assert line == ("nice supcoord solve $WORK/apo_s0_fold_13x7.problem.json --out=$OUT/x.json --instances $INSTANCES "
                    "$KAIJU_PYTHON benchmarks/kaiju_side.py $REUSE/apo_s0_mdp_fold.json")
    assert not MACHINE_PATH.search(line.encode())
