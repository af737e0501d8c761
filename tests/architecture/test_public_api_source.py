"""The public API has one source, ``supcoord._LAZY``: the package docstring's table,
the ``TYPE_CHECKING`` imports, the table of ``docs/api.md`` and the README's package
map must agree with it (they are written by hand, so they are checked here)."""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path

import supcoord
from supcoord import errors

ROOT = Path(__file__).resolve().parents[2]
INIT = ROOT / "src" / "supcoord" / "__init__.py"
_NAME = re.compile(r"`([A-Za-z_][A-Za-z0-9_]*)`")


def _public() -> set[str]:
    return set(supcoord.__all__)


def test_all_is_lazy_plus_the_top_level_names():
    assert _public() == set(supcoord._LAZY) | set(errors.__all__) | {"__version__", "sync", "allevents"}


def _docstring_table() -> set[str]:
    """The names of the package docstring's table (between its ``====`` rules)."""
    doc = supcoord.__doc__ or ""
    rules = [m.start() for m in re.finditer(r"^=+ +=+$", doc, re.M)]
    assert len(rules) == 3, "the docstring's table has a header rule, a separator and an end rule"
    table = doc[rules[1]:rules[2]]
    names = set(re.findall(r":(?:class|func|data):`([A-Za-z_][A-Za-z0-9_]*)`", table))
    if ":class:`SupcoordError` and its subclasses" in table:
        names |= set(errors.__all__)
    return names


def test_the_docstring_table_lists_the_public_api():
    listed = _docstring_table()
    assert listed == _public() - {"__version__"}, (
        f"missing from the table: {sorted(_public() - {'__version__'} - listed)}; "
        f"not public: {sorted(listed - _public())}")


def _type_checking_imports() -> dict[str, str]:
    """name -> absolute module of the imports under ``if TYPE_CHECKING:`` in ``__init__``."""
    tree = ast.parse(INIT.read_text())
    blocks = [n for n in tree.body if isinstance(n, ast.If) and isinstance(n.test, ast.Name)
              and n.test.id == "TYPE_CHECKING"]
    assert len(blocks) == 1
    out: dict[str, str] = {}
    for node in ast.walk(blocks[0]):
        if isinstance(node, ast.ImportFrom):
            assert node.level == 1, "relative imports of the package's own modules"
            for alias in node.names:
                assert alias.name not in out, f"{alias.name} imported twice"
                out[alias.asname or alias.name] = f"supcoord.{node.module}"
    return out


def test_type_checking_imports_agree_with_lazy():
    seen = _type_checking_imports()
    assert seen == supcoord._LAZY, (
        f"only in _LAZY: {sorted(set(supcoord._LAZY) - set(seen))}; "
        f"only under TYPE_CHECKING: {sorted(set(seen) - set(supcoord._LAZY))}; "
        f"other module: {sorted(n for n in seen.keys() & supcoord._LAZY.keys() if seen[n] != supcoord._LAZY[n])}")


def _api_md_rows() -> list[tuple[list[str], str]]:
    """``(names, package)`` of each row of the table under ``| names | package |`` in docs/api.md."""
    text = (ROOT / "docs" / "api.md").read_text()
    start = text.index("| names | package |")
    rows = []
    for line in text[start:].splitlines()[2:]:
        if not line.startswith("|"):
            break
        names, package = (cell.strip() for cell in line.strip("|").split("|", 1))
        rows.append((_NAME.findall(names), re.match(r"`([\w.]+)`", package).group(1)))
    return rows


def test_the_api_page_table_lists_the_public_api():
    listed = [name for names, _ in _api_md_rows() for name in names]
    assert len(listed) == len(set(listed)), "a name listed twice"
    assert set(listed) == _public(), (
        f"missing from docs/api.md: {sorted(_public() - set(listed))}; not public: {sorted(set(listed) - _public())}")


def test_each_name_of_the_api_page_is_in_its_package():
    wrong = []
    for names, package in _api_md_rows():
        module = importlib.import_module(package)
        for name in names:
            mine = getattr(module, name, None)
            top = getattr(supcoord, name)
            if mine is None or (inspect.unwrap(top) if callable(top) else top) is not mine:
                wrong.append(f"{name} in {package}")
    assert not wrong, f"not importable (as the same object) where docs/api.md says: {wrong}"


def test_the_readme_names_every_package():
    text = (ROOT / "README.md").read_text()
    start = text.index("| package | what |")
    table = text[start:text.index("\n\n", start)]
    listed = set(re.findall(r"`(supcoord(?:\.[a-z_]+)*)`", table))
    packages = {".".join(p.relative_to(ROOT / "src").parent.parts)
                for p in (ROOT / "src" / "supcoord").rglob("__init__.py")} - {"supcoord"}
    assert packages <= listed, f"packages missing from the README's map: {sorted(packages - listed)}"
    assert listed - packages <= {"supcoord.progress", "supcoord.outputs", "supcoord.errors"}, "no such package"
