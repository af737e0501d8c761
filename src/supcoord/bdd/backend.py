"""The ``dd`` backends: choosing one, and the size of a shared BDD DAG without CUDD.

``dd.cudd`` (CUDD, compiled) is used when it imports, otherwise ``dd.autoref`` (pure
Python); both share the ``Function`` interface, named here once as the structural type
:class:`BDD` that every module annotating a BDD node imports.

References
----------
- I. Filippidis et al., the ``dd`` package (tulip-control/dd).
"""

from __future__ import annotations

from typing import Any, Iterable, Protocol

from ..errors import InputError

__all__ = ["BDD", "load_backend", "quiet_cudd_out_of_memory", "dag_size", "raise_stack_limit", "STACK_BYTES"]

class BDD(Protocol):
    """A node of a ``dd`` BDD (``dd.cudd.Function`` or ``dd.autoref.Function``): the
    operations supcoord uses on one.

    Structural (a :class:`typing.Protocol`): both backends' classes have these members
    without deriving from this class, as in ``dd._abc.Operator``.  ``var`` is ``None`` on
    the constants; with complemented edges ``low`` and ``high`` are the children of the
    regular node and ``negated`` says whether this edge is complemented.

    Examples
    --------
    >>> from supcoord.bdd import Context
    >>> ctx = Context()
    >>> x = ctx.add_variable("x", 4)              # two bits, x_1 x_0
    >>> u: BDD = ctx.eq("x", 2)
    >>> (u & ~u) == ctx.false, sorted(u.support), u.var
    (True, ['x_0', 'x_1'], 'x_1')

    References
    ----------
    - I. Filippidis et al., the ``dd`` package, ``dd/_abc.py`` (tulip-control/dd).
    """

    def __invert__(self) -> BDD: ...

    def __and__(self, other: BDD) -> BDD: ...

    def __or__(self, other: BDD) -> BDD: ...

    def __eq__(self, other: object) -> bool: ...

    def __hash__(self) -> int: ...

    def __int__(self) -> int: ...

    @property
    def var(self) -> str | None: ...

    @property
    def level(self) -> int: ...

    @property
    def low(self) -> BDD | None: ...

    @property
    def high(self) -> BDD | None: ...

    @property
    def negated(self) -> bool: ...

    @property
    def support(self) -> set[str]: ...


#: C stack the BDD operations may use (bytes): CUDD's apply recurses once per variable
#: level, so BDDs over ~10^5 variables (the paper's model at 6,000 positioners) overflow
#: the usual 8 MiB and crash the process with a segmentation fault
STACK_BYTES = 2**30


def raise_stack_limit(wanted: int = STACK_BYTES) -> int:
    """Raise this process's soft ``RLIMIT_STACK`` to ``wanted`` bytes (within the hard limit)
    and return the limit now in force.  On Linux the main thread's stack grows on demand up
    to the soft limit checked at the time of growth, so raising it before the deep
    recursion is enough; threads keep the stack they were created with."""
    try:
        import resource
    except ImportError:  # not POSIX: nothing to do
        return 0
    soft, hard = resource.getrlimit(resource.RLIMIT_STACK)
    if soft == resource.RLIM_INFINITY or soft >= wanted:
        return soft
    target = wanted if hard == resource.RLIM_INFINITY else min(hard, wanted)
    try:
        resource.setrlimit(resource.RLIMIT_STACK, (target, hard))
    except (ValueError, OSError):
        return soft
    return target


_QUIETED: set[str] = set()


def quiet_cudd_out_of_memory(module: Any) -> bool:
    """Make CUDD report a failed allocation instead of ending the process.

    CUDD's default out-of-memory handler (``MMoutOfMemory``, used where a node chunk cannot
    be allocated) prints ``CUDD: out of memory allocating N bytes`` and calls ``exit(1)``:
    under a memory limit (:mod:`.memory`) the process would die without a word of JSON.
    Installing CUDD's own ``Cudd_OutOfMemSilent`` (through ``ctypes``, on the extension
    ``module`` of ``dd.cudd``) makes the operation fail instead, which ``dd`` raises as an
    exception.  Returns whether the handler is installed."""
    path = getattr(module, "__file__", None)
    if path is None:
        return False
    if path in _QUIETED:
        return True
    try:
        import ctypes

        lib = ctypes.CDLL(path)
        install = lib.Cudd_InstallOutOfMemoryHandler
        install.restype = ctypes.c_void_p
        install.argtypes = [ctypes.c_void_p]
        install(ctypes.cast(lib.Cudd_OutOfMemSilent, ctypes.c_void_p))
    except (OSError, AttributeError):  # another build of dd: its own handler stays
        return False
    _QUIETED.add(path)
    return True


def load_backend(name: str = "auto"):
    """Return the ``dd`` module for ``name`` in {"auto", "cudd", "autoref"} (for CUDD, after
    :func:`raise_stack_limit`)."""
    if name not in ("auto", "cudd", "autoref"):
        raise InputError(f"unknown BDD backend {name!r} (use auto, cudd or autoref)", value=name)
    if name in ("auto", "cudd"):
        try:
            from dd import cudd as _bdd

            raise_stack_limit()
            quiet_cudd_out_of_memory(_bdd)
            return _bdd
        except ImportError:
            if name == "cudd":
                raise InputError("backend 'cudd' requested but dd.cudd does not import", value=name)
    from dd import autoref as _bdd

    return _bdd


def dag_size(us: Iterable[BDD]) -> int:
    """Number of nodes of the shared DAG of ``us`` (the constant node included), by a walk."""
    seen: set[int] = set()
    stack = list(us)
    while stack:
        f = stack.pop()
        if f.var is None:
            seen.add(-1)
            continue
        key = int(~f) if f.negated else int(f)
        if key in seen:
            continue
        seen.add(key)
        stack.append(f.low)
        stack.append(f.high)
    return len(seen)
