"""The shape of the code in ``src/`` (read from the source, nothing is imported).

- no function has a cyclomatic complexity (radon's) above :data:`MAX_COMPLEXITY` or is
  longer than :data:`MAX_FUNCTION_LINES` lines (from ``def`` to its last line, without its
  docstring: a numpydoc docstring with examples is documentation, not length of code);
- nothing outside ``supcoord.problems`` writes into an object's ``__dict__``
  (``x.__dict__[k] = v``, ``x.__dict__.setdefault(...)``, ...): caches held on a
  ``Problem`` that way are attributes nobody declared.

"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from radon.complexity import cc_visit
from radon.visitors import Function

SRC = Path(__file__).resolve().parents[2] / "src"
MAX_COMPLEXITY = 25
MAX_FUNCTION_LINES = 80
#: ``__dict__`` methods that change it
_DICT_WRITERS = {"setdefault", "update", "pop", "popitem", "clear", "__setitem__", "__delitem__"}

def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted((SRC / "supcoord").rglob("*.py")):
        parts = list(path.with_suffix("").relative_to(SRC).parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = _modules()


def _functions(blocks, prefix: str):
    """(qualified name, radon block) of every function and method, nested ones included."""
    for block in blocks:
        if isinstance(block, Function):
            name = f"{prefix}.{block.fullname}"
            yield name, block
            yield from _functions(block.closures, name)


def _docstring_lines(source: str) -> dict[int, int]:
    """Line of each function's ``def`` -> how many lines its docstring takes."""
    out = {}
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and ast.get_docstring(node) is not None:
            doc = node.body[0]
            out[node.lineno] = doc.end_lineno - doc.lineno + 1
    return out


def shape_violations_of(source: str, module: str = "m") -> dict[str, str]:
    """Every function of ``source`` over a limit -> what it is over, e.g. ``"complexity 41, 118 lines"``."""
    out = {}
    docs = _docstring_lines(source)
    for name, block in _functions(cc_visit(source), module):
        lines = block.endline - block.lineno + 1 - docs.get(block.lineno, 0)
        over = []
        if block.complexity > MAX_COMPLEXITY:
            over.append(f"complexity {block.complexity}")
        if lines > MAX_FUNCTION_LINES:
            over.append(f"{lines} lines")
        if over:
            out[name] = ", ".join(over)
    return out


def shape_violations() -> dict[str, str]:
    """Every function in ``src/`` over a limit -> what it is over."""
    out = {}
    for module, path in MODULES.items():
        out.update(shape_violations_of(path.read_text(encoding="utf-8"), module))
    return out


def _writes_dict(node: ast.AST) -> bool:
    """Whether ``node`` writes into some object's ``__dict__``."""
    def is_dict(n: ast.AST) -> bool:
        return isinstance(n, ast.Attribute) and n.attr == "__dict__"

    if isinstance(node, ast.Subscript) and isinstance(node.ctx, (ast.Store, ast.Del)):
        return is_dict(node.value)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
        return node.func.attr in _DICT_WRITERS and is_dict(node.func.value)
    return False


class _DictWrites(ast.NodeVisitor):
    def __init__(self, module: str):
        self.scope = [module]
        self.found: set[str] = set()

    def _enter(self, node) -> None:
        self.scope.append(node.name)
        self.generic_visit(node)
        self.scope.pop()

    visit_FunctionDef = visit_AsyncFunctionDef = visit_ClassDef = _enter

    def generic_visit(self, node: ast.AST) -> None:
        if _writes_dict(node):
            self.found.add(".".join(self.scope))
        super().generic_visit(node)


def dict_writes() -> set[str]:
    """Qualified names of the functions outside ``supcoord.problems`` that write a ``__dict__``."""
    out: set[str] = set()
    for module, path in MODULES.items():
        if module == "supcoord.problems" or module.startswith("supcoord.problems."):
            continue
        visitor = _DictWrites(module)
        visitor.visit(ast.parse(path.read_text(encoding="utf-8")))
        out |= visitor.found
    return out


def test_no_function_is_too_complex_or_too_long():
    over = shape_violations()
    assert not over, f"over complexity {MAX_COMPLEXITY} or {MAX_FUNCTION_LINES} lines (cut by idea): {over}"


def test_no_dict_writes_outside_problems():
    found = dict_writes()
    assert not found, f"write into __dict__ outside supcoord.problems (hold the cache in an object of its own): {found}"


@pytest.mark.parametrize("source, expected", [
    ("def f(p):\n    p.__dict__['_c'] = 1\n", {"m.f"}),
    ("def f(p):\n    return p.__dict__.setdefault('_c', {})\n", {"m.f"}),
    ("class A:\n    def g(self, p):\n        def h():\n            del p.__dict__['x']\n        return h\n",
     {"m.A.g.h"}),
    ("def f(p):\n    return p.__dict__.get('_c'), dict(p.__dict__)\n", set()),
])
def test_dict_writes_are_found_and_reads_are_not(source, expected):
    visitor = _DictWrites("m")
    visitor.visit(ast.parse(source))
    assert visitor.found == expected


def test_complexity_and_length_are_measured_per_function():
    branches = "\n".join(f"    if x == {i}:\n        return {i}" for i in range(MAX_COMPLEXITY))
    source = f"def busy(x):\n{branches}\n    return -1\n\n\ndef short(x):\n    return x\n"
    found = {name: block.complexity for name, block in _functions(cc_visit(source), "m")}
    assert found == {"m.busy": MAX_COMPLEXITY + 1, "m.short": 1}


def test_a_docstring_does_not_count_as_length():
    body = "\n".join(f"    y{i} = x" for i in range(MAX_FUNCTION_LINES - 2))
    doc = '    """' + "\n".join(["Doc."] * 40) + '\n    """'
    source = f"def documented(x):\n{doc}\n{body}\n    return x\n\n\ndef padded(x):\n{body}\n    y = x\n    z = y\n    return x\n"
    assert _docstring_lines(source) == {1: 41}
    assert set(shape_violations_of(source)) == {"m.padded"}
