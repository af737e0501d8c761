"""How many robots a problem may have: set by the memory there is, checked before allocating.

Planning ``N`` robots takes memory roughly in proportion to ``N`` (the problem's arrays, the
neighbour pairs, the collision tables of the pairs a search touches, the windows' BDDs).
:data:`BYTES_PER_ROBOT` is that proportion with room to spare: DESI's geometry on the
13 × 7 lattice without plan improvement peaked at about 250 KiB per robot at 1,801 robots,
350 KiB at 5,167, 320 KiB at 10,981 and 190 KiB at 19,927 (``benchmarks/results/nextgen.md``),
and the most robots a problem may have is::

    N_max = memory / BYTES_PER_ROBOT

where ``memory`` (:func:`memory_limit`) is the machine's memory, or the process's data or
address-space limit when lower (the command line's ``--max-memory`` sets the data limit).
On a machine of 24 GiB that is 49,152 robots (a hex grid of 127 rings); 16 GiB allow
32,768 (104 rings, 32,761 robots).  A layout is checked against it from its numbers alone (``rings``, or the
length of a list of points) before any array is made, so a typo such as ``rings = 10**9``
is one line at once, not an exhausted machine.
"""

from __future__ import annotations

import os
import resource

from ..errors import InputError

__all__ = ["BYTES_PER_ROBOT", "memory_limit", "robot_limit", "check_robot_count"]

#: estimated peak bytes per robot of posing and planning a problem (module docstring)
BYTES_PER_ROBOT = 512 * 2**10


def memory_limit() -> int:
    """The memory a problem may use (bytes): the machine's physical memory, or the soft
    ``RLIMIT_DATA`` or ``RLIMIT_AS`` of this process when lower.

    Returns
    -------
    int
        Bytes; at least 1 GiB where the machine does not say (no ``sysconf``).

    Examples
    --------
    >>> memory_limit() > 0
    True
    """
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        total = 2**30
    for limit in (resource.RLIMIT_DATA, resource.RLIMIT_AS):
        soft, _ = resource.getrlimit(limit)
        if soft != resource.RLIM_INFINITY and soft > 0:
            total = min(total, soft)
    return int(total)


def robot_limit(memory: int | None = None) -> int:
    """The most robots a problem may have: ``memory // BYTES_PER_ROBOT``.

    Parameters
    ----------
    memory : int, optional
        Bytes available; default :func:`memory_limit`.

    Returns
    -------
    int
        Robots (at least 1).

    Examples
    --------
    >>> robot_limit(16 * 2**30)
    32768
    """
    return max(1, int(memory_limit() if memory is None else memory) // BYTES_PER_ROBOT)


def check_robot_count(n: int, field: str, value: object, where: str | None = None,
                      memory: int | None = None) -> None:
    """Refuse ``n`` robots when they would not fit in memory, naming the field and its value.

    Parameters
    ----------
    n : int
        Robots the layout would have.
    field, value
        The field that sets ``n`` (e.g. ``"layout.rings"``) and its value, for the message.
    where : str, optional
        The file, for the message.
    memory : int, optional
        Bytes available; default :func:`memory_limit`.

    Raises
    ------
    InputError
        ``n`` exceeds :func:`robot_limit`.

    Examples
    --------
    >>> check_robot_count(32_761, "layout.rings", 104, memory=16 * 2**30)
    >>> check_robot_count(3 * 10**18, "layout.rings", 10**9, memory=16 * 2**30)
    Traceback (most recent call last):
    ...
    supcoord.errors.InputError: layout.rings = 1000000000 gives 3000000000000000000 robots, more than the 32768 that 16.0 GiB of memory allow (512 KiB per robot)
    """
    memory = memory_limit() if memory is None else int(memory)
    limit = robot_limit(memory)
    if n > limit:
        raise InputError(f"{field} = {value} gives {n} robots, more than the {limit} that {memory / 2**30:.1f} GiB "
                         f"of memory allow ({BYTES_PER_ROBOT // 2**10} KiB per robot)", value=value, where=where)
