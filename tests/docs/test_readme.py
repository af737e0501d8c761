"""README.md keeps its promises: the two commands, the Python example, the links, no placeholders."""

from __future__ import annotations

import doctest
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"


@pytest.mark.slow
def test_readme_python_example_runs(monkeypatch):
    """The ``>>>`` block under "From Python" is a doctest, so its outputs cannot go stale."""
    monkeypatch.setenv("MPLBACKEND", "Agg")
    result = doctest.testfile(str(README), module_relative=False, report=True,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 10 and result.failed == 0, result


def test_readme_starts_with_two_sentences_then_the_two_commands():
    text = README.read_text()
    body = text.split("\n", 1)[1]
    intro = body.split("```", 1)[0]
    paragraph = [line for line in intro.strip().splitlines() if line.strip()][:2]
    assert all(line.rstrip().endswith(".") for line in paragraph)
    commands = re.findall(r"```bash\n(.*?)\n```", text, flags=re.S)
    assert commands[0] == "python3 -m venv .venv && .venv/bin/pip install -q . && .venv/bin/supcoord demo"
    assert commands[1] == ("python3 -m venv .venv && .venv/bin/pip install -q -e '.[test]' && "
                           ".venv/bin/python -m pytest -q -n 2")
    # .ci/run runs the same test command
    assert "\n.venv/bin/python -m pytest -q -n 2\n" in (ROOT / ".ci" / "run").read_text()


def test_readme_links_and_images_resolve_and_no_placeholder_is_left():
    text = README.read_text()
    targets = re.findall(r"\]\(([^)#\s]+)\)", text)
    assert targets, "README links nothing"
    missing = [t for t in targets if not t.startswith("http") and not (ROOT / t).exists()]
    assert not missing, f"README links to missing files: {missing}"
    leftovers = re.findall(r"\b[A-Z]{4,}_[A-Z_]+\b", text)
    assert not leftovers, f"unfilled placeholders in README: {leftovers}"
