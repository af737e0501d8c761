"""The layout rules of docs/architecture.md, read from the source (no import is executed).

- every ``supcoord`` import, at module level or inside a function, goes to a package the
  importer may use (the table below), so imports only go downward;
- the module graph (function-level imports included) has no cycle;
- no module is over 600 lines (one idea per module; an idea that needs more is two);
- test oracles (``supcoord.testing``) are not part of the top-level API.
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"

#: package -> the packages its modules may import (besides itself); docs/architecture.md
ALLOWED: dict[str, set[str]] = {
    "errors": set(),
    "progress": {"errors"},
    "outputs": {"errors"},
    "bdd": {"errors", "progress"},
    "des": {"bdd", "errors", "progress", "outputs"},
    "synthesis": {"des", "bdd", "errors", "progress"},
    "geometry": {"errors"},
    "instruments": {"geometry", "errors"},
    "problems": {"geometry", "instruments", "errors", "outputs", "progress"},
    "paper": {"synthesis", "des", "bdd", "geometry", "errors", "progress", "outputs"},
    "planning": {"problems", "geometry", "synthesis", "des", "bdd", "errors", "progress"},
    "figures": {"problems", "geometry", "errors", "outputs"},
    "testing": {"planning", "problems", "geometry", "bdd", "errors"},
    "study": {"paper", "planning", "problems", "geometry", "figures", "synthesis", "des", "bdd", "errors", "progress",
              "outputs"},
    # the command line reads __version__ from the top level
    "cli": {"__init__", "paper", "planning", "problems", "geometry", "figures", "synthesis", "des", "bdd",
            "errors", "progress", "study", "outputs"},
    # the top level re-exports lazily; _compat forwards old names on demand (importlib)
    "__init__": {"errors", "_compat", "_boundary", "des", "synthesis", "bdd", "paper", "geometry", "problems", "planning",
                 "figures", "instruments", "progress", "outputs"},
    "_compat": set(),
    "_boundary": {"errors"},
}
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted((SRC / "supcoord").rglob("*.py")):
        parts = list(path.with_suffix("").relative_to(SRC).parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = _modules()


def _is_package(name: str) -> bool:
    return MODULES[name].name == "__init__.py"


def _imports(name: str) -> set[str]:
    """The ``supcoord`` modules ``name`` imports anywhere in its body (resolved to module names)."""
    path = MODULES[name]
    package = name if _is_package(name) else name.rsplit(".", 1)[0]
    found: set[str] = set()

    def add(target: str, names: list[str]) -> None:
        # ``from pkg import mod`` imports the module pkg.mod; ``from mod import f`` imports mod
        subs = [f"{target}.{n}" for n in names if f"{target}.{n}" in MODULES]
        found.update(subs or ([target] if target in MODULES else []))

    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target == "supcoord" or target.startswith("supcoord."):
                add(target, [a.name for a in node.names])
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("supcoord"):
                    add(alias.name, [])
    found.discard(name)
    return found


def _package(module: str) -> str:
    parts = module.split(".")
    if len(parts) == 1:
        return "__init__"
    return parts[1]


GRAPH = {m: _imports(m) for m in MODULES}


def test_every_module_was_read():
    assert {"supcoord.planning.planner", "supcoord.geometry.collision", "supcoord.synthesis.supcon"} <= set(MODULES)
    assert GRAPH["supcoord.planning.planner"], "the parser found no import in a module that has many"


def test_packages_import_only_downward():
    wrong = []
    for module, targets in GRAPH.items():
        own = _package(module)
        for target in targets:
            other = _package(target)
            if other != own and other not in ALLOWED.get(own, set()):
                wrong.append(f"{module} imports {target} ({own} may import {sorted(ALLOWED.get(own, set()))})")
    assert not wrong, "\n".join(wrong)


def test_the_package_table_has_no_cycle():
    # the allowed table itself is a partial order (so 'downward' means something)
    state: dict[str, int] = {}

    def visit(p: str, path: list[str]) -> None:
        if state.get(p) == 1:
            raise AssertionError("cycle in ALLOWED: " + " -> ".join(path + [p]))
        if state.get(p) == 2:
            return
        state[p] = 1
        for q in ALLOWED.get(p, set()):
            if q != "__init__":
                visit(q, path + [p])
        state[p] = 2

    for p in ALLOWED:
        if p != "__init__":
            visit(p, [])


def _cycles() -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan), function-level imports included."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def strong(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in GRAPH[v]:
            # a package's __init__ importing its own modules is how packages work, not a cycle
            if w not in MODULES or (_is_package(v) and w.startswith(v + ".")):
                continue
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(GRAPH):
        if v != "supcoord" and v not in index:  # the top level imports everything lazily by design
            strong(v)
    return out


def test_no_import_cycle_between_modules():
    assert _cycles() == []


def test_the_cycle_detector_finds_a_cycle():
    # mutation check of the test itself: a synthetic back edge must be reported
    GRAPH["supcoord.bdd.context"].add("supcoord.synthesis.supcon")
    try:
        assert any("supcoord.bdd.context" in c for c in _cycles())
    finally:
        GRAPH["supcoord.bdd.context"].discard("supcoord.synthesis.supcon")


def test_no_module_is_over_600_lines():
    long = {m: n for m, p in MODULES.items() if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, long


def test_test_oracles_are_not_top_level_api():
    import supcoord

    assert not {"bfs_plan_naive", "optimal_makespan_naive", "reachable_naive"} & set(supcoord.__all__)
    assert not any(m.startswith("supcoord.testing") for m in ast.literal_eval(_lazy_table()).values())


def _lazy_table() -> str:
    tree = ast.parse(MODULES["supcoord"].read_text())
    for node in tree.body:
        if isinstance(node, ast.AnnAssign) and getattr(node.target, "id", "") == "_LAZY":
            return ast.unparse(node.value)
    raise AssertionError("supcoord/__init__.py has no _LAZY table")


def test_the_geometric_oracle_shares_no_code_with_what_it_checks():
    """supcoord.testing.oracle imports nothing of supcoord but errors and itself: not the
    geometry, the planner or the problems it is an independent opinion about."""
    oracle = [name for name in MODULES if name.startswith("supcoord.testing.oracle")]
    assert len(oracle) > 3
    for name in oracle:
        outside = {m for m in _imports(name) if not m.startswith("supcoord.testing.oracle")}
        assert outside <= {"supcoord.errors"}, (name, sorted(outside))


def test_no_two_modules_share_a_name():
    """A module's name says which one it is: ``planning.move_layers`` and
    ``synthesis.layers``, not two ``layers``."""
    by_name: dict[str, list[str]] = {}
    for module in MODULES:
        by_name.setdefault(module.rsplit(".", 1)[-1], []).append(module)
    packages = {m for m in MODULES if any(other.startswith(m + ".") for other in MODULES)}
    repeated = {name: mods for name, mods in by_name.items() if len(mods) > 1 and not set(mods) <= packages}
    assert not repeated, repeated


def test_the_validators_geometry_shares_no_code_with_the_planners():
    """``problems.validate_motion`` evaluates the arms, the segment distances and the sampled
    motions with its own code (docs/architecture.md, "The validator"): a bug in
    ``supcoord.geometry`` cannot pass both the planner and its check."""
    imported = _imports("supcoord.problems.validate_motion")
    assert not {m for m in imported if m.startswith(("supcoord.geometry", "supcoord.planning"))}, sorted(imported)
