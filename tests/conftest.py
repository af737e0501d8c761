"""Shared test set-up: the helper modules on ``sys.path``, hypothesis' profiles and the
``bdd_backend`` fixture.

Tests live in folders named like the packages they test (``tests/planning``, ``tests/synthesis``,
...); the helpers they share (``oracle``, ``routes``, ``strategies``, ``backends``) live in
``tests/helpers`` and are imported by their plain names (``from strategies import ...``), as the
suite runs with ``--import-mode=importlib``.
"""

import compileall
import importlib.util
import os
import sys

import pytest
from hypothesis import HealthCheck, settings

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "helpers"))

settings.register_profile(
    "default", max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
settings.register_profile("quick", max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))

#: the BDD backends of ``dd`` that supcoord runs on: CUDD (C) and the pure-Python ``autoref``; both
#: come with ``dd``, so a missing one fails the tests that use it instead of skipping them
BDD_BACKENDS = ("cudd", "autoref")


@pytest.fixture(scope="session", params=BDD_BACKENDS)
def bdd_backend(request) -> str:
    """Each BDD backend's name in turn, for ``Context(bdd_backend)``: a test that asks for this
    fixture runs once per backend (as ``dd``'s own backend-neutral tests do).  Session-scoped,
    so hypothesis' ``@given`` tests may use it too."""
    return request.param


def _expected_length(item: pytest.Item) -> float:
    """How long a test may take, as it declares it: a slow-marked test's time limit (its
    ``timeout`` mark, else the default of ``pyproject.toml``); 0 for the others."""
    if item.get_closest_marker("slow") is None:
        return 0.0
    mark = item.get_closest_marker("timeout")
    return float(mark.args[0]) if mark is not None and mark.args else float(item.config.getini("timeout") or 0)


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Run the slow tests first, the longest declared time limit first, and the others in their
    order: with ``-n 2`` the workers take the tests in this order, two at a time
    (``--maxschedchunk=2`` in ``pyproject.toml``), so the minute-long tests start
    at once on both workers and the short ones fill the end, instead of one long test running
    alone at the end.  The sort is stable: tests of equal rank keep their order."""
    items.sort(key=lambda item: -_expected_length(item))


def pytest_configure(config: pytest.Config) -> None:
    """Byte-compile supcoord's modules once, in the main process, before any test runs.

    The suite starts hundreds of Python processes that import supcoord (the command-line and
    documentation tests, every study case, the notebooks' kernels).  An editable install
    leaves the sources uncompiled, and where ``PYTHONDONTWRITEBYTECODE`` is set no process
    writes its compiled modules either, so each of them compiled every module it imported
    again: about 0.5 s of CPU a process.  A ``pip install .`` compiles them the same way at
    install time.  Nothing is written where the modules are already compiled or the folder is
    read-only."""
    if hasattr(config, "workerinput"):  # an xdist worker: the main process has done it
        return
    spec = importlib.util.find_spec("supcoord")
    for folder in (spec.submodule_search_locations or []) if spec else []:
        if os.access(folder, os.W_OK):
            compileall.compile_dir(folder, quiet=1)
