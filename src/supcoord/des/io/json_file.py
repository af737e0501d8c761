"""JSON generators, the format of ``docs/formats.md``::

    {"name": "G", "states": N, "init": 0, "marked": [0, ...],
     "events": [{"name": "71", "controllable": true}, ...],
     "transitions": [[src, "event", dst], ...]}

States are ``0…N-1``; ``init`` is ``null`` only for the empty generator (``N = 0``);
optional ``"state_names"`` (``N`` strings) is kept.  Validation is strict: a missing
or ill-typed field, a state out of range, an unknown or duplicate event raise
:class:`~supcoord.errors.FormatError` naming the field and the value (``where`` =
the file); two transitions on one event from one state raise
:class:`~supcoord.errors.NondeterminismError`.
"""

from __future__ import annotations

import json
import os
from typing import Any, Callable, NotRequired, TypedDict

from ...errors import FormatError, InputError, NondeterminismError
from ..generator import Event, Generator
from .files import read_bytes, write_atomic

__all__ = ["GeneratorDocument", "EventDocument", "generator_to_dict", "generator_from_dict", "parse_json", "format_json", "read_json", "write_json"]

_FIELDS = {"name", "states", "init", "marked", "events", "transitions", "state_names"}


class EventDocument(TypedDict):
    """An event of a JSON generator."""

    name: str
    controllable: bool


class GeneratorDocument(TypedDict):
    """A JSON generator (module docstring): states ``0…states-1``, transitions as
    ``[source, event name, target]``."""

    name: str
    states: int
    init: int | None
    marked: list[int]
    events: list[EventDocument]
    transitions: list[list[int | str]]
    state_names: NotRequired[list[str]]


def generator_to_dict(g: Generator) -> GeneratorDocument:
    """``g`` as the JSON object of ``docs/formats.md``."""
    d: GeneratorDocument = {
        "name": g.name,
        "states": g.n_states,
        "init": g.init,
        "marked": sorted(g.marked),
        "events": [{"name": e.name, "controllable": e.controllable} for e in g.alphabet],
        "transitions": [[s, e, t] for s, e, t in g.transitions()],
    }
    if g.state_names is not None:
        d["state_names"] = list(g.state_names)
    return d


def _is_int(x: Any) -> bool:
    return isinstance(x, int) and not isinstance(x, bool)


def generator_from_dict(d: Any, where: str = "<json>") -> Generator:
    """Validate a JSON object and build the :class:`Generator` it describes."""

    def bad(field: str, value: Any, msg: str) -> FormatError:
        shown = json.dumps(value)[:80] if _jsonable(value) else repr(value)[:80]
        return FormatError(f"field {field!r}: {msg} (got {shown})", value=value, where=where)

    if not isinstance(d, dict):
        raise bad("<top>", d, "a generator is a JSON object")
    unknown = sorted(set(d) - _FIELDS)
    if unknown:
        raise bad(unknown[0], d[unknown[0]], f"unknown field; expected some of {sorted(_FIELDS)}")
    for key in ("states", "events", "transitions"):
        if key not in d:
            raise FormatError(f"missing field {key!r}", value=key, where=where)
    name = d.get("name", "G")
    if not isinstance(name, str):
        raise bad("name", name, "must be a string")
    n = d["states"]
    if not _is_int(n) or n < 0:
        raise bad("states", n, "must be a non-negative integer")

    def state(field: str, q: Any) -> int:
        if not _is_int(q) or not 0 <= q < n:
            raise bad(field, q, f"must be a state number in 0..{n - 1}" if n else "no states exist")
        return q

    init = d.get("init", 0 if n else None)
    if n == 0:
        if init is not None:
            raise bad("init", init, "must be null for a generator without states")
    else:
        init = state("init", init)
    marked = d.get("marked", [])
    if not isinstance(marked, list):
        raise bad("marked", marked, "must be a list of state numbers")
    marked = [state("marked", q) for q in marked]
    events = _events(d["events"], bad)
    seen = _transitions(d["transitions"], events, state, bad, where)
    names = d.get("state_names")
    if names is not None and (not isinstance(names, list) or len(names) != n or not all(isinstance(x, str) for x in names)):
        raise bad("state_names", names, f"must be a list of {n} strings")
    try:
        return Generator(n, events.values(), [(s, e, q) for (s, e), q in seen.items()], init, marked, name, names)
    except InputError as exc:  # pragma: no cover - everything is validated above
        raise FormatError(exc.message, value=exc.value, where=where) from None


def _events(raw: Any, bad: Callable[[str, Any, str], FormatError]) -> dict[str, Event]:
    """The ``"events"`` field: name -> :class:`Event`, in file order."""
    if not isinstance(raw, list):
        raise bad("events", raw, "must be a list of {\"name\", \"controllable\"} objects")
    events: dict[str, Event] = {}
    for e in raw:
        if not isinstance(e, dict) or set(e) != {"name", "controllable"}:
            raise bad("events", e, "each event is {\"name\": string, \"controllable\": bool}")
        if not isinstance(e["name"], str) or not e["name"]:
            raise bad("events.name", e["name"], "must be a non-empty string")
        if not isinstance(e["controllable"], bool):
            raise bad("events.controllable", e["controllable"], "must be true or false")
        if e["name"] in events:
            raise bad("events.name", e["name"], "duplicate event")
        events[e["name"]] = Event(e["name"], e["controllable"])
    return events


def _transitions(
    raw: Any, events: dict[str, Event], state: Callable[[str, Any], int],
    bad: Callable[[str, Any, str], FormatError], where: str,
) -> dict[tuple[int, str], int]:
    """The ``"transitions"`` field as ``{(source, event): target}``, in file order."""
    if not isinstance(raw, list):
        raise bad("transitions", raw, "must be a list of [src, \"event\", dst]")
    seen: dict[tuple[int, str], int] = {}
    for t in raw:
        if not isinstance(t, list) or len(t) != 3 or not isinstance(t[1], str):
            raise bad("transitions", t, "each transition is [src, \"event\", dst]")
        s, e, q = state("transitions", t[0]), t[1], state("transitions", t[2])
        if e not in events:
            raise bad("transitions", t, f"event {e!r} is not in 'events'")
        old = seen.setdefault((s, e), q)
        if old != q:
            raise NondeterminismError(
                f"field 'transitions': state {s} has two transitions on {e!r}, to {old} and to {q}",
                value=(s, e, (old, q)), where=where,
            )
    return seen


def _jsonable(x: Any) -> bool:
    try:
        json.dumps(x)
        return True
    except (TypeError, ValueError):
        return False


def read_json(path: str | os.PathLike) -> Generator:
    """Read a JSON generator file."""
    return parse_json(read_bytes(path), os.fspath(path))


def parse_json(text: str | bytes, where: str = "<json>") -> Generator:
    """Parse JSON text into a :class:`Generator` (strictly validated)."""
    try:
        d = json.loads(text)
    except (ValueError, RecursionError) as exc:
        line = getattr(exc, "lineno", None)
        at = f"line {line}: " if line else ""
        raise FormatError(f"{at}invalid JSON: {getattr(exc, 'msg', exc)}", value=str(exc), where=where) from None
    return generator_from_dict(d, where)


def format_json(g: Generator) -> str:
    """The JSON text of ``g``: one field per line, one event and one transition per line."""
    d = generator_to_dict(g)
    lines = []
    for key, value in d.items():
        if key in ("events", "transitions") and value:
            inner = ",\n".join("    " + json.dumps(x) for x in value)
            lines.append(f'  "{key}": [\n{inner}\n  ]')
        else:
            lines.append(f"  {json.dumps(key)}: {json.dumps(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def write_json(g: Generator, path: str | os.PathLike) -> None:
    """Write ``g`` as JSON (:func:`format_json`)."""
    write_atomic(path, [format_json(g)], "utf-8")
