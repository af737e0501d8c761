"""Mutations of input files for fuzzing the readers (tests/cli/test_fuzz.py, benchmarks/fuzz_campaign.py).

Every mutator takes the bytes of a valid file and a seeded :class:`random.Random` and
returns hostile bytes, so a failing case is reproduced from its seed alone:

- :func:`mutate_bytes`: one byte-level edit — a bit pattern flipped, a run deleted,
  random bytes inserted, the tail truncated or a run duplicated;
- :func:`mutate_json`: half the time a byte edit, otherwise one JSON value (anywhere in
  the document, the whole document included) replaced by :func:`hostile_value`;
- :func:`mutate_gen`: a byte edit, a number replaced by a huge, negative or malformed
  one, a tag dropped, doubled or renamed, or a ``<Consecutive>`` range of 10^7+ states.

References
----------
- B. P. Miller, L. Fredriksen, B. So, An empirical study of the reliability of UNIX
  utilities, CACM 33(12), 1990 (fuzz testing).
"""

from __future__ import annotations

import json
import random
import re
from typing import Any, Iterator

__all__ = ["mutate_bytes", "mutate_json", "mutate_gen", "hostile_value"]

_HUGE = [10**12, -1, 0, 2**63, 2**64 + 1, -(2**70), 10**400]


def hostile_value(rng: random.Random) -> Any:
    """A JSON value chosen to break a reader: huge or negative integers, NaN/inf, strings,
    null, booleans, short lists and objects, deep nesting."""
    kind = rng.randrange(9)
    if kind == 0:
        return rng.choice(_HUGE)
    if kind == 1:
        return rng.randint(-(2**70), 2**70)
    if kind == 2:
        return rng.choice([float("nan"), float("inf"), -float("inf"), 1e308, -0.0, 0.5, 1.7])
    if kind == 3:
        return "".join(rng.choice("aZ9 \"\\\u00e9\u2603<>") for _ in range(rng.randrange(12)))
    if kind == 4:
        return None
    if kind == 5:
        return rng.random() < 0.5
    if kind == 6:
        return [rng.randint(-3, 3) for _ in range(rng.randrange(5))]
    if kind == 7:
        return {rng.choice("abxyz"): rng.randint(-2, 2) for _ in range(rng.randrange(3))}
    return _Deep(rng.choice([5, 50, 5000]))


class _Deep:
    """Lists nested ``depth`` deep, written as text (``json.dumps`` itself would recurse)."""

    def __init__(self, depth: int):
        self.depth = depth


def mutate_bytes(data: bytes, rng: random.Random) -> bytes:
    """One byte-level edit of ``data`` (module docstring)."""
    if not data:
        return bytes(rng.randrange(256) for _ in range(rng.randrange(1, 20)))
    i = rng.randrange(len(data))
    kind = rng.randrange(5)
    if kind == 0:
        return data[:i] + bytes([data[i] ^ rng.randrange(1, 256)]) + data[i + 1:]
    if kind == 1:
        return data[:i] + data[min(len(data), i + rng.randrange(1, 41)):]
    if kind == 2:
        return data[:i] + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 21))) + data[i:]
    if kind == 3:
        return data[:i]
    j = min(len(data), i + rng.randrange(1, 81))
    return data[:j] + data[i:j] + data[j:]


def _paths(value: Any, path: tuple = ()) -> Iterator[tuple]:
    yield path
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _paths(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _paths(v, path + (i,))


def _replace(value: Any, path: tuple, new: Any) -> Any:
    if not path:
        return new
    value[path[0]] = _replace(value[path[0]], path[1:], new)
    return value


def mutate_json(data: bytes, rng: random.Random) -> bytes:
    """A byte edit, or one value of the JSON document ``data`` replaced by :func:`hostile_value`."""
    if rng.random() < 0.5:
        return mutate_bytes(data, rng)
    doc = json.loads(data)
    path = rng.choice(list(_paths(doc)))
    value = hostile_value(rng)
    if isinstance(value, _Deep):
        marker = "\u0000deep\u0000"
        text = json.dumps(_replace(doc, path, marker), allow_nan=True)
        return text.replace(json.dumps(marker), "[" * value.depth + "]" * value.depth).encode()
    return json.dumps(_replace(doc, path, value), allow_nan=True).encode()


def mutate_gen(data: bytes, rng: random.Random) -> bytes:
    """A byte edit, a number, a tag or a state range of a ``.gen`` file changed (module docstring)."""
    text = data.decode("latin-1")
    kind = rng.randrange(4)
    if kind == 0:
        return mutate_bytes(data, rng)
    if kind == 1:
        numbers = list(re.finditer(r"\b\d+\b", text))
        if numbers:
            m = rng.choice(numbers)
            text = text[:m.start()] + rng.choice(["0", "-1", "10000000000", "9" * 5000, "1e9", "0x10"]) + text[m.end():]
    elif kind == 2:
        tags = list(re.finditer(r"</?[A-Za-z]+>", text))
        if tags:
            m = rng.choice(tags)
            text = text[:m.start()] + rng.choice(["", m.group(0) * 2, "<Foo>"]) + text[m.end():]
    else:
        top = rng.choice(["10000000", "99999999999"])
        text = text.replace("<States>", f"<States> <Consecutive> 1 {top} </Consecutive>", 1)
    return text.encode("latin-1", errors="replace")
