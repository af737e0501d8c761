"""A study: a declared set of cases, read from TOML or JSON or built in Python.

Definitions (``docs/study.md`` has the file format with examples):

- a **block** is one entry of ``cases``: a ``kind`` (:mod:`.kinds`) and its parameters;
  a parameter given as a list is an **axis**, and the block stands for every combination
  of its axes (a grid; a block without lists is one case);
- a **case** is one point of a block: the kind and the complete parameters (defaults
  filled in), identified by its **parameters key** (a hash of the kind and the
  parameters) and, once a code version is fixed, by its **key** (parameters key and
  version): a case whose key is in the database is done, so a study resumes where it
  stopped;
- **limits**: each case runs with a time limit (seconds, default 600) and a memory limit
  (resident memory, a hard limit, default 4 GiB), set for the study and overridable per block;
- ``skip_larger = "positioners"`` in a block: once a case runs out of time or memory, the
  block's cases with a larger value of that parameter and otherwise the same parameters
  (any seed) are not run (they are recorded as ``skipped``).

>>> study = study_from_dict({"name": "tiny", "time_limit": 30, "cases": [
...     {"kind": "paper", "steps": 6, "positioners": [2, 3], "seed": [0, 1]}]})
>>> len(study.cases), study.cases[0].series, study.cases[0].params["route"]
(4, 'paper literal modular', 'modular')
>>> study.cases[0].key("1.0") != study.cases[0].key("1.1")
True
"""

from __future__ import annotations

import hashlib
import itertools
import json
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import FormatError, InputError
from ..progress import summary_html, summary_repr
from .kinds import KINDS, LIST_VALUED, check_params, series_of, size_of

__all__ = [
    "DEFAULT_MEMORY_LIMIT_MB",
    "DEFAULT_TIME_LIMIT",
    "Case",
    "Study",
    "load_study",
    "parse_memory",
    "study_from_dict",
]

DEFAULT_TIME_LIMIT = 600.0
DEFAULT_MEMORY_LIMIT_MB = 4096.0
#: the keys of a block that are not parameters of the kind
BLOCK_KEYS = {"kind", "time_limit", "memory_limit", "skip_larger", "series"}
STUDY_KEYS = {"name", "description", "database", "time_limit", "memory_limit", "workers", "pythonpath", "cases"}
_UNITS = {"b": 1 / 2**20, "kb": 1 / 1024, "kib": 1 / 1024, "mb": 1, "mib": 1, "gb": 1024, "gib": 1024,
          "tb": 2**20, "tib": 2**20}


@dataclass(frozen=True)
class Case:
    """One computation of a study (see the module docstring)."""

    kind: str
    params: dict[str, Any]
    series: str
    size: int | None = None
    positioners: int | None = None
    time_limit: float = DEFAULT_TIME_LIMIT
    memory_limit_mb: float | None = DEFAULT_MEMORY_LIMIT_MB
    block: int = 0
    skip_larger: str | None = None
    #: folders put first on the case process's ``sys.path`` (the study's ``pythonpath``)
    pythonpath: tuple[str, ...] = ()

    @property
    def params_json(self) -> str:
        """The kind and the parameters as canonical JSON (sorted keys)."""
        return json.dumps({"kind": self.kind, **self.params}, sort_keys=True, separators=(",", ":"))

    @property
    def params_key(self) -> str:
        return hashlib.sha1(self.params_json.encode()).hexdigest()[:16]

    def key(self, version: str) -> str:
        """The case's identity in a database: same parameters and same code version."""
        return hashlib.sha1(f"{self.params_json}|{version}".encode()).hexdigest()[:16]

    def describe(self) -> str:
        """``paper literal modular, positioners=100, seed=0`` (for progress lines)."""
        shown = {k: v for k, v in self.params.items() if k in ("positioners", "rings", "size", "seed", "steps")
                 and v is not None}
        return ", ".join([self.series] + [f"{k}={v}" for k, v in shown.items()])

    def __repr__(self) -> str:
        return summary_repr("Case", {"case": self.describe(), "time_limit": self.time_limit,
                                     "memory_limit_mb": self.memory_limit_mb})


@dataclass
class Study:
    """A named list of cases, the database it writes to and its default number of workers."""

    name: str
    cases: list[Case]
    database: Path | None = None
    description: str = ""
    workers: int | None = None
    path: Path | None = None
    blocks: list[dict[str, Any]] = field(default_factory=list)

    def database_path(self, override: str | Path | None = None) -> Path:
        """``override``, else the file's ``database``, else ``NAME.sqlite`` beside the study file."""
        if override is not None:
            return Path(override)
        if self.database is not None:
            return self.database
        folder = self.path.parent if self.path is not None else Path.cwd()
        return folder / f"{self.name}.sqlite"

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: name, numbers of cases and series, the database."""
        return {"name": self.name, "cases": len(self.cases), "series": len({c.series for c in self.cases}),
                "database": str(self.database_path())}

    def __repr__(self) -> str:
        return summary_repr("Study", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("Study", self.summary())


def parse_memory(value: Any, where: str) -> float | None:
    """A memory limit in MB: a number (MB), ``"6 GiB"``, ``"500 MB"``, or ``"none"``/``false``."""
    if value is None or value is False or (isinstance(value, str) and value.strip().lower() == "none"):
        return None
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value > 0:
        return float(value)
    m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+)\s*([a-zA-Z]*)\s*", value) if isinstance(value, str) else None
    unit = (m.group(2) or "mb").lower() if m else ""
    if not m or unit not in _UNITS or float(m.group(1)) <= 0:
        raise InputError(f"must be a positive size such as 4096 (MB), '6 GiB' or '500 MB', or 'none', got {value!r}",
                         value=value, where=where)
    return float(m.group(1)) * _UNITS[unit]


def _time(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0 or value == float("inf"):
        raise InputError(f"must be a positive number of seconds, got {value!r}", value=value, where=where)
    return float(value)


def load_study(path: str | Path) -> Study:
    """Read a study from a ``.toml`` or ``.json`` file (the format of ``docs/study.md``)."""
    p = Path(path)
    if not p.is_file():
        raise InputError("study file not found" if not p.exists() else "is not a file", value=str(path), where=str(path))
    text = p.read_text(encoding="utf-8")
    try:
        if p.suffix.lower() == ".json":
            data = json.loads(text)
        else:
            data = tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as exc:
        raise FormatError(f"not valid {'JSON' if p.suffix.lower() == '.json' else 'TOML'}: {exc}",
                          value=str(path), where=str(path)) from None
    if not isinstance(data, dict):
        raise FormatError("must hold a table (JSON object) with 'cases'", value=str(path), where=str(path))
    return study_from_dict(data, name=p.stem, path=p)


def study_from_dict(data: dict[str, Any], *, name: str | None = None, path: Path | None = None) -> Study:
    """A :class:`Study` from the parsed file (or a dict built in Python)."""
    where = str(path) if path is not None else "study"
    base = path.resolve().parent if path is not None else None
    unknown = sorted(set(data) - STUDY_KEYS)
    if unknown:
        raise InputError(f"unknown field (known: {', '.join(sorted(STUDY_KEYS))})", value=unknown[0],
                         where=f"{where}: {unknown[0]}")
    blocks = data.get("cases")
    if not isinstance(blocks, list) or not blocks or not all(isinstance(b, dict) for b in blocks):
        raise InputError("must be a non-empty list of tables ([[cases]] in TOML)", value=blocks, where=f"{where}: cases")
    study_name = data.get("name", name or "study")
    if not isinstance(study_name, str) or not re.fullmatch(r"[\w.-]+", study_name):
        raise InputError("must be a name of letters, digits, '.', '-' or '_'", value=study_name, where=f"{where}: name")
    time_limit = _time(data.get("time_limit", DEFAULT_TIME_LIMIT), f"{where}: time_limit")
    memory = parse_memory(data.get("memory_limit", DEFAULT_MEMORY_LIMIT_MB), f"{where}: memory_limit")
    workers = data.get("workers")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 0):
        raise InputError("must be an integer >= 0", value=workers, where=f"{where}: workers")
    database = _database(data.get("database"), base, where)
    folders = _pythonpath(data.get("pythonpath", []), base, where)
    cases: list[Case] = []
    seen: set[str] = set()
    for i, block in enumerate(blocks):
        for case in _expand(block, i, f"{where}: cases[{i}]", base, time_limit, memory, folders):
            if case.params_key not in seen:  # the same case twice in a study is run once
                seen.add(case.params_key)
                cases.append(case)
    description = data.get("description", "")
    return Study(study_name, cases, database, description if isinstance(description, str) else "", workers, path,
                 [dict(b) for b in blocks])


def _database(database: Any, base: Path | None, where: str) -> Path | None:
    """The study's ``database`` field: a file name, relative to the study file's folder."""
    if database is None:
        return None
    if not isinstance(database, str) or not database:
        raise InputError("must be a file name", value=database, where=f"{where}: database")
    return Path(database) if base is None or Path(database).is_absolute() else (base / database).resolve()


def _pythonpath(pythonpath: Any, base: Path | None, where: str) -> tuple[str, ...]:
    """The study's ``pythonpath`` field: folders, relative to the study file's folder."""
    if not isinstance(pythonpath, list) or not all(isinstance(p, str) and p for p in pythonpath):
        raise InputError("must be a list of folders", value=pythonpath, where=f"{where}: pythonpath")
    return tuple(str((base / p).resolve()) if base is not None and not Path(p).is_absolute() else p
                 for p in pythonpath)


def _expand(block: dict[str, Any], index: int, where: str, base: Path | None, time_limit: float,
            memory: float | None, pythonpath: tuple[str, ...] = ()) -> list[Case]:
    kind = block.get("kind")
    if kind not in KINDS:
        raise InputError(f"must be one of {', '.join(sorted(KINDS))}", value=kind, where=f"{where}.kind")
    limit = _time(block.get("time_limit", time_limit), f"{where}.time_limit")
    mem = parse_memory(block.get("memory_limit", memory), f"{where}.memory_limit") if "memory_limit" in block else memory
    params = {k: v for k, v in block.items() if k not in BLOCK_KEYS}
    skip = block.get("skip_larger")
    if skip is not None and skip not in KINDS[kind]:
        raise InputError(f"must name a parameter of kind {kind!r}, got {skip!r}", value=skip, where=f"{where}.skip_larger")
    series = block.get("series")
    if series is not None and not isinstance(series, str):
        raise InputError("must be a string", value=series, where=f"{where}.series")
    axes = {k: v for k, v in params.items() if isinstance(v, list) and (k not in LIST_VALUED or
                                                                         all(isinstance(x, list) for x in v))}
    for k, v in axes.items():
        if not v:
            raise InputError("an empty list leaves no case to run", value=v, where=f"{where}.{k}")
    out = []
    for values in itertools.product(*axes.values()):
        point = {**params, **dict(zip(axes, values))}
        p = check_params(kind, point, where, base)
        size, positioners = size_of(kind, p)
        out.append(Case(kind, p, series or series_of(kind, p), size, positioners, limit, mem, index, skip, pythonpath))
    return out
