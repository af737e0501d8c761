"""The notebooks in ``notebooks/`` run top to bottom (small parameters) with nbmake.

Each notebook is executed in a fresh Jupyter kernel by nbmake's runner with
``SUPCOORD_NOTEBOOK_SMALL=1``, which the first cell (the parameters, tagged
``parameters``) turns into CI sizes; a cell that raises fails the test with the
cell's traceback, and so does an output holding a warning, a traceback or a study case
that crashed.  The same run by hand: ``SUPCOORD_NOTEBOOK_SMALL=1 python -m pytest
--nbmake notebooks/`` (the notebooks also pick small sizes under pytest by themselves).
The stored notebooks carry no outputs, so diffs stay readable; a notebook listed in
``STORED_OUTPUTS`` (the real wok: its plan takes minutes, so a reader sees one run) carries
the outputs of one clean run, within a size limit.
"""

from __future__ import annotations

import json
from pathlib import Path

import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[2] / "notebooks").glob("*.ipynb"))
#: generous per-cell limit; CI-sized notebooks take seconds per cell
CELL_TIMEOUT = 600
#: notebooks stored with the outputs of one run -> the largest size of those outputs (bytes)
STORED_OUTPUTS = {"04_real_wok.ipynb": 150_000}


def test_the_three_notebooks_exist():
    names = [p.name for p in NOTEBOOKS]
    for prefix in ("01_", "02_", "03_", "04_"):
        assert any(n.startswith(prefix) for n in names), f"no notebook {prefix}* in notebooks/: {names}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_is_stored_clean_with_a_parameters_cell(path):
    nb = nbformat.read(str(path), as_version=4)
    nbformat.validate(nb)
    if path.name in STORED_OUTPUTS:
        size = sum(len(json.dumps(c.outputs)) for c in nb.cells if c.cell_type == "code")
        assert size <= STORED_OUTPUTS[path.name], f"{path.name}: {size} bytes of outputs, more than {STORED_OUTPUTS[path.name]}"
        noisy = [(i, text[:300]) for i, text in _outputs(nb) if any(w in text for w in NOISE)]
        assert not noisy, f"{path.name}: stored outputs with a warning, a traceback or a crashed case: {noisy}"
    else:
        dirty = [i for i, c in enumerate(nb.cells) if c.cell_type == "code" and (c.outputs or c.execution_count)]
        assert not dirty, f"{path.name}: cells {dirty} carry outputs (strip them before committing)"
    first = next(c for c in nb.cells if c.cell_type == "code")
    assert "parameters" in first.metadata.get("tags", []), f"{path.name}: the first code cell is not tagged 'parameters'"
    assert "SMALL" in first.source, f"{path.name}: the parameters cell does not define SMALL"


@pytest.mark.slow
@pytest.mark.timeout(300)  # notebook 02 runs a live study on Dask: over a minute on a loaded 2-core machine
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_runs(path, monkeypatch):
    from nbmake.nb_run import NotebookRun

    monkeypatch.setenv("SUPCOORD_NOTEBOOK_SMALL", "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    result = NotebookRun(path, CELL_TIMEOUT).execute()
    if result.error is not None:
        pytest.fail(f"{path.name}, cell {result.error.failing_cell_index}: {result.error.summary}\n"
                    f"{result.error.trace}", pytrace=False)
    noisy = [(i, text[:300]) for i, text in _outputs(result.nb) if any(w in text for w in NOISE)]
    assert not noisy, f"{path.name}: outputs with a warning, a traceback or a crashed case: {noisy}"


#: what the outputs of a clean run never hold (a study case that crashed prints ": crashed")
NOISE = ("Warning", "Traceback", ": crashed")


def _outputs(nb) -> list[tuple[int, str]]:
    """``(cell index, text)`` of every stream and text output of an executed notebook."""
    out = []
    for i, cell in enumerate(nb.cells):
        for o in cell.get("outputs", []):
            if o.get("output_type") == "stream":
                out.append((i, o.get("text", "")))
            elif "data" in o:
                out.append((i, str(o["data"].get("text/plain", ""))))
    return out
