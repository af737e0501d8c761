"""The public API importable from ``supcoord``: names, docstrings, lightness, determinism."""

from __future__ import annotations

import doctest
import inspect
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import supcoord


def test_every_public_name_imports():
    missing = [name for name in supcoord.__all__ if not hasattr(supcoord, name)]
    assert not missing, f"names in supcoord.__all__ that do not import: {missing}"
    assert len(set(supcoord.__all__)) == len(supcoord.__all__)


def test_every_public_name_is_documented():
    undocumented = []
    for name in supcoord.__all__:
        obj = getattr(supcoord, name)
        if inspect.isclass(obj) or inspect.isfunction(obj):
            doc = obj.__dict__.get("__doc__") if inspect.isclass(obj) else obj.__doc__
            if not doc or not doc.strip():
                undocumented.append(name)
        elif name not in (supcoord.__doc__ or "") and name != "__version__":
            undocumented.append(name)  # data: named in the package docstring
    assert not undocumented, f"public names without a docstring: {undocumented}"


def test_dir_lists_the_lazy_names():
    assert set(supcoord.__all__) <= set(dir(supcoord))


def test_unknown_attribute_raises_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        supcoord.nope  # noqa: B018


def test_import_is_light():
    code = (
        "import sys, supcoord; "
        "heavy = [m for m in ('matplotlib', 'dd', 'numpy', 'tqdm') if m in sys.modules]; "
        "print(','.join(heavy))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"'import supcoord' imported {out.stdout.strip()}"


def test_figures_stay_lazy_until_asked_for():
    code = (
        "import sys, supcoord; supcoord.ccc; supcoord.paper_example; supcoord.Problem; "
        "assert 'matplotlib' not in sys.modules, 'matplotlib imported too early'; "
        "supcoord.save_plan_gif; assert 'matplotlib' in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_errors_form_one_hierarchy():
    for name in ("InputError", "FormatError", "ModelError", "NondeterminismError", "AlphabetError", "BudgetExceeded"):
        assert issubclass(getattr(supcoord, name), supcoord.SupcoordError)


# -- sync / allevents dispatch --------------------------------------------------------


def _pair():
    a, b, c = supcoord.Event("a", True), supcoord.Event("b", True), supcoord.Event("c", False)
    G1 = supcoord.Generator(2, [a, c], [(0, "a", 1), (1, "c", 0)], 0, [0], name="G1")
    G2 = supcoord.Generator(2, [b, c], [(0, "b", 1), (1, "c", 0)], 0, [0], name="G2")
    return G1, G2


def test_sync_explicit_and_symbolic_agree():
    G1, G2 = _pair()
    ctx = supcoord.Context()
    S = supcoord.sync(supcoord.from_explicit(ctx, G1), supcoord.from_explicit(ctx, G2))
    X = supcoord.sync(G1, G2)
    assert supcoord.to_explicit(S).canonical().same_as(X.canonical())
    assert supcoord.to_explicit(supcoord.allevents(S)).n_states == supcoord.allevents(X).n_states == 1


def test_sync_rejects_mixed_kinds_with_a_project_error():
    G1, G2 = _pair()
    with pytest.raises(supcoord.InputError, match="all explicit or all symbolic"):
        supcoord.sync(G1, supcoord.from_explicit(supcoord.Context(), G2))
    with pytest.raises(supcoord.InputError):
        supcoord.sync()
    with pytest.raises(supcoord.InputError):
        supcoord.allevents("G")


# -- determinism: the same seed gives the same results -------------------------------


def _stable(payload: dict) -> dict:
    return {k: v for k, v in payload.items() if k not in ("seconds", "timings")}


@pytest.mark.parametrize("model, size, steps", [("literal", 6, 6), ("coupled", 3, 8)])
def test_paper_model_is_deterministic_for_a_seed(model, size, steps):
    a = supcoord.solve_paper(size, steps, model, seed=1)
    b = supcoord.solve_paper(size, steps, model, seed=1)
    assert _stable(a) == _stable(b)
    assert supcoord.random_instance(12, 12, seed=3) == supcoord.random_instance(12, 12, seed=3)
    assert supcoord.random_instance(12, 12, seed=3) != supcoord.random_instance(12, 12, seed=4)


def test_paper_example_witness_is_deterministic_across_contexts():
    runs = []
    for _ in range(2):
        G, E = supcoord.coupled_models(supcoord.CoupledModel(supcoord.paper_example()), supcoord.Context())
        r = supcoord.ccc(supcoord.supcon(G, E).supervisor)
        runs.append((r.forcible, r.rank, r.witness, r.layers))
    assert runs[0] == runs[1]


def test_random_problems_are_deterministic_for_a_seed():
    layout = {"kind": "hex", "rings": 2, "pitch": 22.4}
    kin = {"kind": "rotary", "arm": 15.0, "steps": 12}
    p1, p2 = (supcoord.random_problem(layout, kin, 2.0, seed=11) for _ in range(2))
    assert np.array_equal(p1.start, p2.start) and np.array_equal(p1.target, p2.target)
    assert list(p1.priority) == list(p2.priority)
    q1, q2 = (supcoord.preset_problem("sdss-v", rings=1, seed=2, alpha_steps=12, beta_steps=7) for _ in range(2))
    assert np.array_equal(q1.start, q2.start) and np.array_equal(q1.target, q2.target)
    other = supcoord.random_problem(layout, kin, 2.0, seed=12)
    assert not (np.array_equal(p1.start, other.start) and np.array_equal(p1.target, other.target))


# -- docs/api.md: every public name with a runnable example ---------------------------

API_MD = Path(__file__).resolve().parents[2] / "docs" / "api.md"


def test_api_reference_examples_run(monkeypatch):
    """The examples of docs/api.md, run as doctests (so the reference cannot go stale)."""
    monkeypatch.setenv("MPLBACKEND", "Agg")
    result = doctest.testfile(str(API_MD), module_relative=False, report=True,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 50 and result.failed == 0, result


def _example_names(text: str) -> set[str]:
    """Names used as ``sc.NAME`` / ``supcoord.NAME`` / ``from supcoord import NAME`` in ``>>>`` lines."""
    code = "\n".join(line.split(">>> ", 1)[1] if ">>> " in line else line.split("... ", 1)[1]
                     for line in text.splitlines() if line.lstrip().startswith((">>> ", "... ")))
    found = set(re.findall(r"\b(?:sc|supcoord)\.(\w+)", code))
    for names in re.findall(r"from supcoord import ([\w, ]+)", code):
        found |= {n.strip() for n in names.split(",")}
    return found


def test_every_public_name_has_a_runnable_example():
    """In its own docstring (run by pytest's doctest collection) or in docs/api.md."""
    in_reference = _example_names(API_MD.read_text(encoding="utf-8"))
    lacking = []
    for name in supcoord.__all__:
        obj = getattr(supcoord, name)
        doc = (obj.__dict__.get("__doc__") if inspect.isclass(obj) else getattr(obj, "__doc__", None)) or ""
        if name not in in_reference and not (callable(obj) and ">>>" in doc):
            lacking.append(name)
    assert not lacking, f"public names with no example in their docstring or docs/api.md: {lacking}"


def test_the_package_is_typed():
    root = Path(supcoord.__file__).resolve().parent
    assert (root / "py.typed").is_file()
    pyproject = (root.parents[1] / "pyproject.toml").read_text(encoding="utf-8")
    assert re.search(r'supcoord = \[[^\]]*"py\.typed"', pyproject), "py.typed is not in the package data"


def _run_json(argv: list[str], hashseed: str) -> dict:
    import json
    import os

    env = {**os.environ, "PYTHONHASHSEED": hashseed}
    proc = subprocess.run([sys.executable, "-m", "supcoord.cli", *argv, "--json", "--quiet"], capture_output=True,
                          text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


@pytest.mark.slow
def test_results_do_not_depend_on_string_hashing(tmp_path):
    """Two processes with different PYTHONHASHSEED (set and dict-of-str iteration orders
    differ) give the same supervisor, witness and plan: determinism across runs, not
    only within one process."""
    import json

    problem = supcoord.random_problem({"kind": "hex", "rings": 1, "pitch": 22.4},
                                      {"kind": "rotary", "arm": 15.0, "steps": 12}, 2.0, seed=3)
    path = tmp_path / "problem.json"
    problem.dump(path)
    runs = {
        "paper": ["paper", "--positioners", "3", "--steps", "8", "--model", "coupled", "--seed", "0"],
        "solve": ["solve", str(path)],
    }
    for name, argv in runs.items():
        a, b = (_stable(_run_json(argv, seed)) for seed in ("1", "2"))
        a.pop("stats", None), b.pop("stats", None)
        assert a == b, f"{name}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"


def test_concepts_examples_run(monkeypatch):
    """docs/concepts.md's worked examples, run as doctests."""
    path = API_MD.parent / "concepts.md"
    result = doctest.testfile(str(path), module_relative=False, report=True,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 20 and result.failed == 0, result


#: the user documentation this test file guards (other pages belong to their modules' owners)
USER_DOCS = ["index.md", "concepts.md", "cli.md", "formats.md", "api.md", "performance.md"]


def _slug(heading: str) -> str:
    """GitHub's anchor of a markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


@pytest.mark.parametrize("page", USER_DOCS)
def test_doc_links_resolve(page):
    """Every relative link of the page names an existing file and, with '#', an existing heading."""
    docs = API_MD.parent
    text = (docs / page).read_text(encoding="utf-8")
    broken = []
    for link in re.findall(r"\]\(([^)\s]+)\)", text):
        if link.startswith(("http://", "https://", "mailto:")):
            continue
        path, _, anchor = link.partition("#")
        target = (docs / path) if path else docs / page
        if not target.exists():
            broken.append(link)
        elif anchor and target.suffix == ".md":
            headings = re.findall(r"^#+ (.*)$", target.read_text(encoding="utf-8"), re.M)
            if anchor not in {_slug(h) for h in headings}:
                broken.append(link)
    assert not broken, f"docs/{page}: broken links {broken}"
