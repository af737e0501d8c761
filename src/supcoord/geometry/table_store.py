"""Memory-bounded stores for the collision tables of many distinct pairs.

A focal plane whose robots each have their own geometry (an instrument's measured arms,
each robot's own lattice through its exact start and target angles) shares no table
between pairs: the APO wok has 3,713 neighbour pairs, and at 19 × 10 positions its
float distance tables alone took 1 GB, its swept tables another 1 GB (one byte per entry).
These stores keep what must stay as compact as it can be, and what can be recomputed
only while it is recent:

- :class:`RecentArrays`: a least-recently-used cache bounded in bytes (the distance
  tables: a distance table is recomputed on demand when a plan improvement or a
  simultaneous check needs it again);
- :class:`PackedTables`: Boolean tables stored bit-packed (8 entries a byte,
  ``numpy.packbits`` on the last axis), with the most recently read ones kept unpacked in
  a :class:`RecentArrays` (the static, swept and blocked tables; the planner's hot readers
  take single bits or columns from :meth:`PackedTables.packed`).

A grid of identical robots has a handful of distinct tables, which stay cached whole.
Arrays handed out are read-only: a caller that changes a table would change every pair
that shares it.
"""

from __future__ import annotations

import ctypes
import ctypes.util
from collections import OrderedDict
from typing import Any, Hashable

import numpy as np

__all__ = ["RecentArrays", "PackedTables", "release_free_heap"]

_TRIM: list[Any] = []  # glibc's malloc_trim, or None where there is none (looked up once)


def release_free_heap() -> None:
    """Return the C heap's free pages to the system: glibc's ``malloc_trim(0)``, nothing on
    other C libraries.  Once glibc has raised its memory-map threshold, numpy's tables of a
    few MB come from the heap, and the small packed tables kept between them stop it from
    shrinking: after building the APO wok's tables at 37 × 19 the process held 4.7 GB, of
    which 2.3 GB were such free pages (2.4 GB after a trim).  Dask's workers trim the same way."""
    if not _TRIM:
        trim = None
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
            trim = getattr(libc, "malloc_trim", None)
        except OSError:
            pass
        _TRIM.append(trim)
    if _TRIM[0] is not None:
        _TRIM[0](0)


class RecentArrays:
    """Arrays by key, the least recently used dropped once they hold more than
    ``max_bytes`` (the newest is always kept, whatever its size)."""

    def __init__(self, max_bytes: int):
        self.max_bytes = int(max_bytes)
        self._items: OrderedDict[Hashable, np.ndarray] = OrderedDict()
        self.nbytes = 0

    def __contains__(self, key: Hashable) -> bool:
        return key in self._items

    def __len__(self) -> int:
        return len(self._items)

    def get(self, key: Hashable) -> np.ndarray | None:
        out = self._items.get(key)
        if out is not None:
            self._items.move_to_end(key)
        return out

    def put(self, key: Hashable, value: np.ndarray) -> np.ndarray:
        """Store ``value`` (made read-only) under ``key``; returns it."""
        old = self._items.pop(key, None)
        if old is not None:
            self.nbytes -= old.nbytes
        value.flags.writeable = False
        self._items[key] = value
        self.nbytes += value.nbytes
        while self.nbytes > self.max_bytes and len(self._items) > 1:
            _, dropped = self._items.popitem(last=False)
            self.nbytes -= dropped.nbytes
        return value


class PackedTables:
    """Boolean tables kept bit-packed on their last axis; :meth:`get` returns the table
    unpacked (read-only), the most recent ones cached up to ``unpacked_bytes``."""

    def __init__(self, unpacked_bytes: int):
        self._packed: dict[Hashable, tuple[np.ndarray, int]] = {}
        self._recent = RecentArrays(unpacked_bytes)
        self.packed_bytes = 0

    def __contains__(self, key: Hashable) -> bool:
        return key in self._packed

    def __len__(self) -> int:
        return len(self._packed)

    def put(self, key: Hashable, table: np.ndarray) -> np.ndarray:
        """Store the Boolean ``table`` under ``key`` (a first value stays); returns the stored one."""
        if key in self._packed:
            return self.get(key)
        table = np.asarray(table, dtype=bool)
        packed = np.packbits(table, axis=-1)
        packed.flags.writeable = False
        self._packed[key] = (packed, table.shape[-1])
        self.packed_bytes += packed.nbytes
        return self._recent.put(key, table)

    def packed(self, key: Hashable) -> np.ndarray:
        """The stored bits (read-only): entry ``[..., j]`` of the table is bit ``7 − j % 8``
        of byte ``[..., j // 8]``."""
        return self._packed[key][0]

    def bit(self, key: Hashable, m: int, i: int, j: int) -> bool:
        """Entry ``[m, i, j]`` of a three-axis table, from the bits."""
        return bool(self._packed[key][0][m, i, j >> 3] >> (7 - (j & 7)) & 1)

    def column(self, key: Hashable, m: int, j: int) -> np.ndarray:
        """``[m, :, j]`` of a three-axis table, from the bits."""
        return ((self._packed[key][0][m, :, j >> 3] >> (7 - (j & 7))) & 1).astype(bool)

    def row(self, key: Hashable, m: int, i: int) -> np.ndarray:
        """``[m, i, :]`` of a three-axis table, from the bits."""
        packed, count = self._packed[key]
        return np.unpackbits(packed[m, i], count=count).astype(bool)

    def get(self, key: Hashable) -> np.ndarray:
        out = self._recent.get(key)
        if out is None:
            packed, count = self._packed[key]
            out = self._recent.put(key, np.unpackbits(packed, axis=-1, count=count).astype(bool))
        return out
