"""docs/testing.md names the tests that check each part; every one it names must exist."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "testing.md"
# `tests/x/test_y.py` or `tests/x/test_y.py::test_z[param]` or `benchmarks/...` in backquotes
NAMED = re.compile(r"`((?:tests|benchmarks)/[^`\s:]+)(?:::([A-Za-z_][A-Za-z0-9_]*)(\[[^`]*\])?)?`")


def _named() -> list[tuple[str, str | None]]:
    return [(m.group(1), m.group(2)) for m in NAMED.finditer(DOC.read_text())]


def _functions(path: Path) -> set[str]:
    return {n.name for n in ast.walk(ast.parse(path.read_text()))
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}


def test_testing_doc_names_many_tests():
    # the table and the mutation sections name tests of most packages
    assert len({p for p, _ in _named() if p.startswith("tests/")}) >= 15


def test_every_test_file_and_function_named_in_testing_md_exists():
    missing = []
    for path, func in _named():
        p = ROOT / path
        if not p.exists():
            missing.append(path)
        elif func and func not in _functions(p):
            missing.append(f"{path}::{func}")
    assert not missing, f"docs/testing.md names tests that do not exist: {missing}"
