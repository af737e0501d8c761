"""The BDD context: finite-domain variables with primed twins over ``dd``.

A :class:`Context` owns one BDD manager and the finite-domain (integer) variables
declared in it.  A variable ``x`` with domain ``{0, …, size-1}`` is bit-blasted into
``b = max(1, ⌈log2 size⌉)`` Boolean variables ``x_{b-1} … x_0`` (most significant bit
first), each declared together with its primed twin ``x_i'`` right below it, so the
order is ``x_{b-1}, x_{b-1}', …, x_0, x_0'`` (interleaved twins keep transition
relations small).  Variables are laid out in declaration order; callers choose that
order (see :mod:`supcoord.bdd.ordering`) and may let CUDD reorder dynamically.

Sets of states are BDDs over unprimed bits, relations over unprimed and primed
bits; ``prime``/``unprime`` rename through ``let`` only.

Backends: ``dd.cudd`` (CUDD, compiled) when it imports, otherwise ``dd.autoref``
(pure Python); ``backend="cudd"`` or ``"autoref"`` selects one explicitly
(:mod:`.backend`).  Fixpoints report progress and check their :class:`Budget`
(:mod:`.budget`) through :meth:`Context.check_budget`.

References
----------
- R. E. Bryant, Graph-based algorithms for Boolean function manipulation, IEEE TC 1986.
- I. Filippidis et al., the ``dd`` package (tulip-control/dd); ``omega`` for the
  primed-twin convention.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from numbers import Integral
from typing import Any, Callable, Iterable, Iterator, Mapping, Sequence

from ..errors import InputError
from .backend import BDD, dag_size, load_backend
from .budget import Budget, ProgressCallback
from .counting import exact_count

__all__ = ["Context", "FiniteVar", "Budget", "load_backend", "ThrottledCheck", "CHECK_EVERY", "MANY_BITS"]
MANY_BITS = 2048  # declared bits beyond which quantifier cubes are kept (Context.and_exist)


@dataclass(frozen=True)
class FiniteVar:
    """A finite-domain variable ``name ∈ {0, …, size-1}`` and its Boolean bits (MSB first)."""

    name: str
    size: int
    bits: tuple[str, ...]
    primed_bits: tuple[str, ...]

    @property
    def width(self) -> int:
        return len(self.bits)


class Context:
    """One BDD manager plus the finite-domain variables declared in it.

    >>> ctx = Context()
    >>> x = ctx.add_variable("x", 5)
    >>> ctx.count(ctx.eq("x", 3) | ctx.eq("x", 4), ["x"])
    2
    >>> ctx.pick(ctx.eq("x", 3), ["x"])
    {'x': 3}
    """

    def __init__(
        self,
        backend: str = "auto",
        *,
        reordering: bool = False,
        budget: Budget | None = None,
        progress: ProgressCallback | None = None, cache_size: int = 2**16,
    ):
        if isinstance(cache_size, bool) or not isinstance(cache_size, int) or not 1 <= cache_size <= 2**30:
            raise InputError(f"must be an integer in [1, 2**30], got {cache_size!r:.60}", where="cache_size")
        self._module = load_backend(backend)
        self.backend = "cudd" if self._module.__name__.endswith("cudd") else "autoref"
        # CUDD grows its computed table on demand; dd's default initial 2^18 slots cost
        # ~20 ms to allocate, which dominates small problems
        self.bdd = self._module.BDD(initial_cache_size=cache_size) if self.backend == "cudd" else self._module.BDD()
        self.bdd.configure(reordering=reordering)
        self.vars: dict[str, FiniteVar] = {}
        self._bit_owner: dict[str, str] = {}
        self.budget = budget or Budget()
        self.progress = progress
        self._peak_nodes = 0
        self._rename_cache: dict[tuple[str, tuple[str, ...]], dict[str, str]] = {}
        self._apa: Callable[[BDD, int], int] | None = None  # CUDD's exact count, once validated
        self._apa_checked = False
        self._live: Callable[[], int] | None = None
        self._cubes: dict[tuple[str, ...], BDD] = {}  # quantifier cubes of a manager of many bits

    # -- declaration ---------------------------------------------------------

    @property
    def true(self) -> BDD:
        return self.bdd.true

    @property
    def false(self) -> BDD:
        return self.bdd.false

    def add_variable(self, name: str, size: int, level: int | None = None) -> FiniteVar:
        """Declare ``name ∈ {0..size-1}`` with primed twin bits, below all earlier ones, or with
        its first bit at ``level`` (the variables below it move down; CUDD only)."""
        if not isinstance(size, int) or size < 1:
            raise InputError(f"variable {name!r} needs a domain size >= 1, got {size!r}", value=size)
        if name in self.vars:
            raise InputError(f"variable {name!r} is already declared", value=name)
        width = max(1, (size - 1).bit_length())
        bits = tuple(f"{name}_{i}" for i in reversed(range(width)))
        primed = tuple(b + "'" for b in bits)
        for b, p in zip(bits, primed):
            if b in self._bit_owner or p in self._bit_owner:
                raise InputError(f"variable {name!r} clashes with the bits of another variable", value=name)
            if level is None:
                self.bdd.declare(b, p)
            else:
                self.bdd.insert_var(b, level)
                self.bdd.insert_var(p, level + 1)
                level += 2
            self._bit_owner[b] = name
            self._bit_owner[p] = name
        var = FiniteVar(name, size, bits, primed)
        self.vars[name] = var
        return var

    def fresh_name(self, prefix: str) -> str:
        """A variable name starting with ``prefix`` that is not declared yet."""
        if prefix not in self.vars:
            return prefix
        i = 1
        while f"{prefix}#{i}" in self.vars:
            i += 1
        return f"{prefix}#{i}"

    def bits(self, names: Iterable[str], primed: bool = False) -> list[str]:
        """The Boolean bits of the given finite-domain variables."""
        out: list[str] = []
        for n in names:
            v = self._var(n)
            out.extend(v.primed_bits if primed else v.bits)
        return out

    def _var(self, name: str) -> FiniteVar:
        try:
            return self.vars[name]
        except KeyError:
            raise InputError(f"unknown variable {name!r}", value=name) from None

    # -- predicates ----------------------------------------------------------

    def eq(self, name: str, value: int, primed: bool = False) -> BDD:
        """``{x : x.name = value}`` (over the primed bits if ``primed``)."""
        return self.assignment({name: value}, primed)

    def assignment(self, values: Mapping[str, int], primed: bool = False) -> BDD:
        """The cube of one (partial) state given as ``{variable: value}``."""
        literals: dict[str, bool] = {}
        for name, value in values.items():
            v = self._var(name)
            if isinstance(value, bool) or not isinstance(value, Integral) or not 0 <= value < v.size:
                raise InputError(f"value {value!r} outside the domain of {name!r} (size {v.size})", value=value)
            value = int(value)
            bits = v.primed_bits if primed else v.bits
            w = v.width
            for i, b in enumerate(bits):
                literals[b] = bool((value >> (w - 1 - i)) & 1)
        return self.cube(literals)

    def cube(self, literals: Mapping[str, bool]) -> BDD:
        """``∧_b (b = literals[b])``, conjoined from the deepest bit up: O(bits) BDD
        operations (``dd.cudd``'s own ``cube`` walks every declared variable, which
        costs milliseconds per cube once tens of thousands of bits are declared)."""
        bdd = self.bdd
        u = self.true
        for b in sorted(literals, key=bdd.level_of_var, reverse=True):
            x = bdd.var(b)
            u = (x if literals[b] else ~x) & u
        return u

    def less_than(self, name: str, bound: int, primed: bool = False) -> BDD:
        """``{x : x.name < bound}``, built bit by bit from the most significant."""
        v = self._var(name)
        bits = v.primed_bits if primed else v.bits
        w = v.width
        if bound >= (1 << w):
            return self.true
        if bound <= 0:
            return self.false
        # x < c  <=>  at the first bit where x and c differ, c has 1 and x has 0
        result = self.false
        equal_so_far = self.true
        for i, b in enumerate(bits):
            cbit = (bound >> (w - 1 - i)) & 1
            xb = self.bdd.var(b)
            if cbit:
                result |= equal_so_far & ~xb
                equal_so_far &= xb
            else:
                equal_so_far &= ~xb
        return result

    def domain(self, names: Iterable[str], primed: bool = False) -> BDD:
        """``{x : x.n < size(n) for every n in names}``: the valid codes."""
        u = self.true
        for n in names:
            v = self._var(n)
            if v.size < (1 << v.width):
                u &= self.less_than(n, v.size, primed)
        return u

    def identity(self, names: Iterable[str]) -> BDD:
        """``{(x, x') : x'.n = x.n for n in names}``."""
        u = self.true
        for n in names:
            v = self._var(n)
            for b, p in zip(v.bits, v.primed_bits):
                u &= self.bdd.apply("<=>", self.bdd.var(b), self.bdd.var(p))
        return u

    # -- renaming and quantification ----------------------------------------

    def _renaming(self, names: Iterable[str] | None, to_primed: bool) -> dict[str, str]:
        key_names = tuple(self.vars) if names is None else tuple(names)
        key = ("p" if to_primed else "u", key_names)
        m = self._rename_cache.get(key)
        if m is None:
            m = {}
            for n in key_names:
                v = self._var(n)
                pairs = zip(v.bits, v.primed_bits) if to_primed else zip(v.primed_bits, v.bits)
                m.update(pairs)
            self._rename_cache[key] = m
        return m

    def prime(self, u: BDD, names: Iterable[str] | None = None) -> BDD:
        """Rename ``x → x'`` for the given variables (all declared if ``None``)."""
        m = self._renaming(names, True)
        return self.bdd.let(m, u) if m else u

    def unprime(self, u: BDD, names: Iterable[str] | None = None) -> BDD:
        """Rename ``x' → x`` for the given variables (all declared if ``None``)."""
        m = self._renaming(names, False)
        return self.bdd.let(m, u) if m else u

    def exist(self, names: Iterable[str], u: BDD, primed: bool = False) -> BDD:
        """``∃ names . u`` over the (primed) bits of the given variables."""
        qbits = self.bits(names, primed)
        if not qbits or self._many_bits():  # many bits: a kept cube (and_exist)
            return self.bdd.apply("\\E", self._cube(qbits), u) if qbits else u
        return self.bdd.exist(qbits, u)

    def and_exist(self, u: BDD, v: BDD, qbits: Sequence[str]) -> BDD:
        """``∃ qbits . u ∧ v`` in one pass (CUDD's AndAbstract) where available; past
        :data:`MANY_BITS` bits (a focal plane's windows) ``dd``'s cube, rebuilt from an array
        over every declared bit at each call (~0.3 ms at 20,000 bits), costs more than the
        operation: there a kept cube quantifies the conjunction (``ExistAbstract``)."""
        if not qbits:
            return u & v
        if self._many_bits():
            return self.bdd.apply("\\E", self._cube(qbits), u & v)
        fn = getattr(self._module, "and_exists", None)
        if fn is not None:
            return fn(u, v, qbits)
        return self.bdd.exist(qbits, u & v)

    def _many_bits(self) -> bool:
        return self.backend == "cudd" and len(self._bit_owner) > MANY_BITS

    def _cube(self, qbits: Sequence[str]) -> BDD:
        """The conjunction of the bits ``qbits`` (positive cube), built once per set of bits."""
        cube = self._cubes.get(tuple(qbits))
        if cube is None:
            self._cubes = {} if len(self._cubes) >= 4096 else self._cubes
            cube = self._cubes[tuple(qbits)] = self.bdd.true
            for b in sorted(set(qbits), key=self.bdd.level_of_var, reverse=True):
                cube = self._cubes[tuple(qbits)] = self.bdd.var(b) & cube
        return cube

    # -- counting, picking, enumerating --------------------------------------

    def count(self, u: BDD, names: Iterable[str], primed_names: Iterable[str] = ()) -> int:
        """Exact number of assignments to the bits of ``names`` (and primed bits of
        ``primed_names``) satisfying ``u``: arbitrary-precision, unlike CUDD's double
        (in C with CUDD's ``Cudd_ApaCountMinterm`` where available, else in Python).

        ``u`` must not depend on other bits; invalid codes are counted as they are, so
        conjoin :meth:`domain` first where sizes are not powers of two.
        """
        care = list(dict.fromkeys(self.bits(names) + self.bits(primed_names, primed=True)))
        support = self.bdd.support(u)
        extra = set(support) - set(care)
        if extra:
            raise InputError(f"count: predicate depends on bits outside the care set: {sorted(extra)[:5]}", value=sorted(extra))
        if not self._apa_checked and self.backend == "cudd" and self.vars:
            from .cudd_count import apa_counter, live_node_reader

            self._apa = apa_counter(self.bdd, self._module, exact_count)
            self._live = live_node_reader(self.bdd, self._apa, self._module)
            self._apa_checked = True
        if self._apa is not None:
            return self._apa(u, len(care))
        return exact_count(self.bdd, u, care)

    @property
    def fast_count(self) -> bool:
        """Whether :meth:`count` runs in C (CUDD's arbitrary-precision count, validated
        on first use; see :mod:`supcoord.bdd.cudd_count`) rather than in Python."""
        if not self._apa_checked and self.backend == "cudd" and self.vars:
            self.count(self.false, [])
        return self._apa is not None

    def pick(self, u: BDD, names: Sequence[str]) -> dict[str, int] | None:
        """One state in ``u`` as ``{variable: value}``, or ``None`` if ``u`` is empty."""
        if u == self.false:
            return None
        care = self.bits(names)
        a = self.bdd.pick(u, care_vars=set(care))
        return self.decode(a, names)

    def enumerate(self, u: BDD, names: Sequence[str], primed_names: Sequence[str] = ()) -> Iterator[dict[str, int]]:
        """Every assignment in ``u`` over ``names`` (and primed values as ``name'``)."""
        care = set(self.bits(names)) | set(self.bits(primed_names, primed=True))
        for a in self.bdd.pick_iter(u, care_vars=care):
            d = self.decode(a, names)
            if primed_names:
                d.update({k + "'": val for k, val in self.decode(a, primed_names, primed=True).items()})
            yield d

    def decode(self, bits: Mapping[str, bool], names: Iterable[str], primed: bool = False) -> dict[str, int]:
        """Turn a bit assignment into ``{variable: value}``."""
        out = {}
        for n in names:
            v = self._var(n)
            value = 0
            for b in v.primed_bits if primed else v.bits:
                value = (value << 1) | int(bool(bits.get(b, False)))
            out[n] = value
        return out

    # -- statistics and budgets ----------------------------------------------

    def node_count(self, *us: BDD) -> int:
        """Number of nodes of the shared DAG of the given functions."""
        if not us:
            return 0
        if self.backend == "cudd":
            return self._module.count_nodes(list(us))
        return dag_size(us)

    def statistics(self) -> dict[str, Any]:
        """The manager's statistics (CUDD's counters; a subset under autoref)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # dd warns that 'mem' is now in bytes
            return dict(self.bdd.statistics())

    def live_nodes(self) -> int:
        """Nodes currently in the manager (CUDD's unique table)."""
        if self._live is not None or self.fast_count:
            return self._live()
        stats = self.statistics()
        return int(stats["n_nodes"]) if "n_nodes" in stats else len(self.bdd)

    def peak_nodes(self) -> int:
        """Largest number of live nodes observed by :meth:`check_budget` (or CUDD's peak)."""
        stats = self.statistics()
        return max(self._peak_nodes, int(stats.get("peak_live_nodes", stats.get("peak_nodes", 0))))

    def check_nodes(self, stage: str, **info: Any) -> None:
        """The node budget alone, cheap enough to follow every BDD operation of an image
        (CUDD's own counters, microseconds): a fixpoint iteration made of many images can
        then overrun ``max_nodes`` by one operation, not by a whole iteration."""
        limit = self.budget.max_nodes
        if limit is not None and (self._live is not None or self.fast_count) and self._live() > limit:
            self.check_budget(stage, inside="image", **info)

    def check_budget(self, stage: str, **info: Any) -> None:
        """Report progress and raise :class:`BudgetExceeded` if a budget ran out."""
        nodes = self.live_nodes()
        self._peak_nodes = max(self._peak_nodes, nodes)
        if self.progress is not None:
            self.progress(stage, {"nodes": nodes, **info})
        self.budget.check(stage, nodes, info)


#: seconds between two checks of a :class:`ThrottledCheck` (a check reads CUDD's statistics)
CHECK_EVERY = 0.2


class ThrottledCheck:
    """``check(stage, **info)``: :meth:`Context.check_budget` at most once every ``every``
    seconds of the budget's clock, the first call always — for fixpoints whose
    iterations cost less than reading CUDD's statistics (milliseconds)."""

    __slots__ = ("ctx", "every", "_last")

    def __init__(self, ctx: Context, every: float = CHECK_EVERY) -> None:
        self.ctx, self.every, self._last = ctx, every, float("-inf")

    def __call__(self, stage: str, **info: Any) -> None:
        now = self.ctx.budget.elapsed()
        if now - self._last >= self.every:
            self.ctx.check_budget(stage, **info)
            self._last = now
