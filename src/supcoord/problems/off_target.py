"""The robots a partial plan leaves off target: who, why, and where each one ends.

A ``partial`` plan (``docs/formats.md``, PLAN.json) puts every robot on its target except
the ones it lists in ``off_target``.  Each entry says where the robot ends (``end``:
``"start"``, back at its start configuration, which is collision-free; ``"folded"``, its
arm folded, :func:`folded_ends`; or ``"parked"`` at the lattice position ``at``, one it reaches
from its start, chosen to free its neighbours' targets) and why it is off target:

- ``"certificate: group [i, j, ...] has no plan with these robots on target"``: the
  robots of the group, with every other robot removed, cannot all reach their targets
  (the planner's infeasibility certificate, :class:`GroupCertificate`); where some robots
  of the group were already off target when it was found, they are named
  (``at_start``: those robots end at their starts in the sub-problem);
- ``"not proven: budget"``: the budget ran out before the robot's target was decided.

This module reads and writes those entries (bounded: at most one per robot, reasons of at
most :data:`MAX_REASON` characters) and turns a problem into the one a partial plan solves
(:func:`partial_end`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FormatError
from ..geometry.kinematics import _is_int
from ..geometry.layout import _short

__all__ = ["OffTarget", "GroupCertificate", "ENDS", "ENTRY_ENDS", "BUDGET_REASON", "MAX_REASON", "group_reason",
           "partial_summary",
           "off_target_to_json", "parse_off_target", "partial_end", "folded_ends"]

#: where a robot off target may end: ``"start"`` (its start configuration) or ``"folded"``
#: (:func:`folded_ends`)
ENDS = ("start", "folded")
#: where a robot of PLAN.json's ``off_target`` may end: :data:`ENDS`, or ``"parked"`` at the
#: lattice position its entry's ``at`` gives (the partial search's parking step)
ENTRY_ENDS = ENDS + ("parked",)
#: the reason of a robot whose target the budget left undecided
BUDGET_REASON = "not proven: budget"
#: longest reason or ``how`` read from a PLAN.json (characters)
MAX_REASON = 4000


@dataclass(frozen=True)
class GroupCertificate:
    """A group of robots that cannot all reach their targets, even with every robot outside
    the group removed: ``members`` (robot indices, sorted), ``how`` it was shown (in words),
    and ``at_start``, the members that were themselves off target (ending at their starts)
    in the sub-problem it was shown for (empty: the group's own targets)."""

    members: tuple[int, ...]
    how: str
    at_start: tuple[int, ...] = ()

    def to_json(self) -> dict:
        """``{"members": [...], "how": "...", "at_start": [...]}``."""
        return {"members": [int(m) for m in self.members], "how": self.how,
                "at_start": [int(m) for m in self.at_start]}


@dataclass(frozen=True)
class OffTarget:
    """One robot a partial plan leaves off its target: ``robot`` (index), ``reason`` (one
    line), ``certificate`` (the group that shows it, or None for ``"not proven: budget"``),
    ``end`` (one of :data:`ENTRY_ENDS`) and ``at``, the lattice position (one index per joint)
    of a robot whose ``end`` is ``"parked"`` (None otherwise)."""

    robot: int
    reason: str
    certificate: GroupCertificate | None
    end: str = "start"
    at: tuple[int, ...] | None = None

    def to_json(self) -> dict:
        """``{"robot", "reason", "certificate", "end"}`` as in PLAN.json, and ``"at"`` where parked."""
        out = {"robot": int(self.robot), "reason": self.reason,
               "certificate": None if self.certificate is None else self.certificate.to_json(), "end": self.end}
        if self.at is not None:
            out["at"] = [int(v) for v in self.at]
        return out


def group_reason(certificate: GroupCertificate) -> str:
    """The one-line reason a certificate gives.

    Examples
    --------
    >>> group_reason(GroupCertificate((12, 40), "exhaustive search"))
    'certificate: group [12, 40] has no plan with these robots on target'
    >>> group_reason(GroupCertificate((1, 2, 3), "exhaustive search", at_start=(3,)))
    'certificate: group [1, 2, 3] has no plan with these robots on target (robot 3 at its start)'
    """
    text = f"certificate: group [{', '.join(map(str, certificate.members))}] has no plan with these robots on target"
    if certificate.at_start:
        which = ", ".join(map(str, certificate.at_start))
        text += f" (robot{'s' if len(certificate.at_start) > 1 else ''} {which} at {'their' if len(certificate.at_start) > 1 else 'its'} start)"
    return text


def partial_summary(n: int, on_target: int, entries: tuple[OffTarget, ...], limit: int = 10) -> str:
    """One line: how many robots reach their targets, and who does not and why (the first
    ``limit`` of them).

    Examples
    --------
    >>> c = GroupCertificate((12, 40), "search")
    >>> partial_summary(41, 40, (OffTarget(12, group_reason(c), c),))
    '40 of 41 robots reach their targets; off target: robot 12 (group [12, 40] has no plan with these robots on target)'
    """
    def why(e: OffTarget) -> str:
        return e.reason[len("certificate: "):] if e.reason.startswith("certificate: ") else e.reason

    def where(e: OffTarget) -> str:
        if e.end == "parked" and e.at is not None:
            return f"; parked at lattice position ({', '.join(map(str, e.at))})"
        return "; ends folded" if e.end == "folded" else ""

    listed = "; ".join(f"robot {e.robot} ({why(e)}{where(e)})" for e in entries[:limit])
    more = f"; and {len(entries) - limit} more" if len(entries) > limit else ""
    return f"{on_target} of {n} robots reach their targets; off target: {listed}{more}"


def off_target_to_json(entries: tuple[OffTarget, ...]) -> list[dict]:
    """PLAN.json's ``off_target`` list."""
    return [e.to_json() for e in entries]


def partial_end(start: np.ndarray, target: np.ndarray, entries: tuple[OffTarget, ...],
                folded: np.ndarray | None = None) -> np.ndarray:
    """The configuration a partial plan ends at: ``target`` with each listed robot at its
    end (its row of ``start``, of ``folded`` where its ``end`` is ``"folded"``, its ``at``
    where ``"parked"``), a new ``(N, J)`` array.

    Examples
    --------
    >>> partial_end(np.array([[0], [1]]), np.array([[5], [6]]), (OffTarget(1, "r", None),)).ravel().tolist()
    [5, 1]
    """
    end = np.array(target, copy=True)
    for e in entries:
        if e.end == "folded" and folded is None:
            raise ValueError(f"robot {e.robot} ends folded: partial_end needs the folded configuration")
        if e.end == "parked":
            if e.at is None:
                raise ValueError(f"robot {e.robot} is parked: its entry needs the position 'at'")
            end[e.robot] = e.at
        else:
            end[e.robot] = (folded if e.end == "folded" else start)[e.robot]
    return end


def folded_ends(problem: Any) -> np.ndarray:
    """Each robot's folded configuration ``(N, J)``: an alpha-beta robot with its alpha joint
    where it starts and its beta joint at the lattice position nearest 180° (the arm folded
    onto itself, its shortest reach; SDSS-V parks at β = 170°, kaiju's folded lattice); a
    rotary robot, which has no joint to fold, at its start.

    Examples
    --------
    >>> from supcoord.problems.problem import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [40, 0]]},
    ...     "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 8, "beta_steps": 5},
    ...     "collision": {"buffer": 1.0}, "start": [[1, 0], [2, 2]], "target": [[0, 0], [0, 0]]})
    >>> folded_ends(p).tolist(), float(p.kin(0).joint_angles_deg(folded_ends(p)[0])[1])
    ([[1, 4], [2, 4]], 180.0)
    """
    out = np.array(problem.start, copy=True)
    for p in range(problem.n):
        kin = problem.kin(p)
        if kin.kind != "alpha-beta":
            continue
        q = np.tile(out[p], (kin.joints[1].steps, 1))
        q[:, 1] = np.arange(kin.joints[1].steps)
        out[p, 1] = int(np.argmin(np.abs(kin.joint_angles_deg(q)[:, 1] - 180.0)))
    return out


def _fail(message: str, value: Any, where: str | None) -> FormatError:
    return FormatError(message, value=value, where=where)


def _robots(value: Any, n: int, name: str, where: str | None) -> tuple[int, ...]:
    """A list of distinct robot indices in ``[0, n)``, sorted."""
    if not isinstance(value, list) or len(value) > n or not all(_is_int(v) and 0 <= v < n for v in value) \
            or len(set(value)) != len(value):
        raise _fail(f"{name} must list distinct robot indices in [0, {n}), got {_short(value)}", value, where)
    return tuple(sorted(int(v) for v in value))


def _text(value: Any, name: str, where: str | None) -> str:
    if not isinstance(value, str) or len(value) > MAX_REASON:
        raise _fail(f"{name} must be a string of at most {MAX_REASON} characters, got {_short(value)}", value, where)
    return value


def _certificate(value: Any, n: int, name: str, where: str | None) -> GroupCertificate | None:
    if value is None:
        return None
    if not isinstance(value, dict) or not set(value) <= {"members", "how", "at_start"} or "members" not in value:
        raise _fail(f"{name} must be null or an object {{members, how, at_start}}, got {_short(value)}", value, where)
    members = _robots(value["members"], n, f"{name}.members", where)
    at_start = _robots(value.get("at_start", []), n, f"{name}.at_start", where)
    if not members or not set(at_start) <= set(members):
        raise _fail(f"{name}: members must be non-empty and hold at_start, got {_short(value)}", value, where)
    return GroupCertificate(members, _text(value.get("how", ""), f"{name}.how", where), at_start)


def _at(value: Any, end: str, name: str, where: str | None) -> tuple[int, ...] | None:
    """A parked robot's lattice position (a short list of non-negative ints); None for other ends."""
    if end != "parked":
        if value is not None:
            raise _fail(f"{name} is given only where end is \"parked\", got {_short(value)}", value, where)
        return None
    if not isinstance(value, list) or not 1 <= len(value) <= 8 or not all(_is_int(v) and v >= 0 for v in value):
        raise _fail(f"{name} must list a parked robot's lattice indices (non-negative ints), got {_short(value)}",
                    value, where)
    return tuple(int(v) for v in value)


def parse_off_target(value: Any, n: int, where: str | None = None) -> tuple[OffTarget, ...]:
    """PLAN.json's ``off_target`` list for a problem of ``n`` robots, checked: at most one
    entry per robot, each ``{"robot", "reason", "certificate", "end"}``.

    Raises
    ------
    FormatError
        A malformed entry, a robot out of range or listed twice, an unknown ``end``.

    Examples
    --------
    >>> parse_off_target([{"robot": 1, "reason": "not proven: budget", "certificate": None, "end": "start"}], 2)
    (OffTarget(robot=1, reason='not proven: budget', certificate=None, end='start', at=None),)
    """
    if not isinstance(value, list) or len(value) > n:
        raise _fail(f"off_target must be a list of at most {n} entries, got {_short(value)}", value, where)
    out, seen = [], set()
    for i, e in enumerate(value):
        name = f"off_target[{i}]"
        if not isinstance(e, dict) or not set(e) <= {"robot", "reason", "certificate", "end", "at"} \
                or "robot" not in e:
            raise _fail(f"{name} must be an object {{robot, reason, certificate, end, at}}, got {_short(e)}", e,
                        where)
        robot = e["robot"]
        if not _is_int(robot) or not 0 <= robot < n or robot in seen:
            raise _fail(f"{name}.robot must be a robot index in [0, {n}) listed once, got {_short(robot)}", robot,
                        where)
        seen.add(robot)
        end = e.get("end", "start")
        if end not in ENTRY_ENDS:
            raise _fail(f"{name}.end must be one of {list(ENTRY_ENDS)}, got {_short(end)}", end, where)
        out.append(OffTarget(int(robot), _text(e.get("reason", ""), f"{name}.reason", where),
                             _certificate(e.get("certificate"), n, f"{name}.certificate", where), end,
                             _at(e.get("at"), end, f"{name}.at", where)))
    return tuple(out)
