"""Studies: declared grids of cases run on Dask, with results in a database.

A **study** (:mod:`.spec`) is a list of cases over the parameters of ``supcoord paper``,
``solve``, ``supcon`` and ``force`` (and of your own functions), read from a TOML or JSON
file or built in Python.  :func:`run_study` (:mod:`.execute`) runs the cases not yet done
on Dask workers, each in a process of its own with a time and a memory limit
(:mod:`.isolate`), and commits each case's row to a SQLite database (:mod:`.store`) as it
ends, so an interrupted study resumes where it stopped.  :func:`results_frame` and
:func:`export_results` (:mod:`.results`) read the database back; :mod:`.plots` draws
time, memory and BDD nodes against positioners, with fitted growth (:mod:`.fit`).
``supcoord study run|show|export|plot`` is the command line; ``docs/study.md`` the guide.

>>> study = study_from_dict({"name": "mini", "cases": [
...     {"kind": "paper", "steps": 6, "positioners": [2, 3]}]})
>>> [c.describe() for c in study.cases]
['paper literal modular, positioners=2, steps=6, seed=0', 'paper literal modular, positioners=3, steps=6, seed=0']
"""

from __future__ import annotations

from .execute import RunSummary, run_study
from .results import export_results, results_frame, results_rows
from .spec import Case, Study, load_study, study_from_dict
from .store import ResultStore

__all__ = [
           "Case",
           "ResultStore",
           "RunSummary",
           "Study",
           "export_results",
           "load_study",
           "results_frame",
           "results_rows",
           "run_study",
           "study_from_dict",
]
