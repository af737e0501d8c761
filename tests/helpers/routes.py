"""What one ``solve`` does on the window route, recorded for the tests that compare it with the
independent oracle (``test_planner_oracle.py``, ``test_exact_oracle.py``): the window searches,
the descents, the certificate's reason — watched through the local route's public observer
(:class:`supcoord.planning.windows.WindowObserver`), not changed — and the forced window settings."""

from __future__ import annotations

from collections import Counter

from supcoord.planning import solve
from supcoord.planning.windows import Local, WindowObserver

#: the window route forced: (levels, descent), with every conflict component left to the windows
FORCED = {
    "windows A": ((18, 60, 200, None), "greedy"),
    "windows B": ((12, 40, 135, None), "none"),
    "windows C": ((30, 300, None), "greedy"),
    "windows D": ((30, 300, None), "none"),
}
CERTIFICATES = {"their conflict component": "conflict component", "this relaxed subproblem": "relaxed subproblem",
                "no other positioner restricts them": "no blocker"}


class Recorder(WindowObserver):
    """Counts what one ``solve`` does in the window route (watched, not changed)."""

    def __init__(self, monkeypatch=None):  # monkeypatch: accepted for the callers, nothing is patched
        self.kinds: Counter = Counter()
        self.run: set[str] = set()
        self.few_solved = 0
        self._by_few = False

    def descended(self, steps):
        if steps:
            self.run.add("descent moved")

    def few_displaced_solved(self, moves):
        self.run.add("few-displaced window solved")
        self.few_solved += 1
        self._by_few = True

    def window(self, outcome):
        by_few, self._by_few = self._by_few, False
        self.run.add("window")
        if outcome.kind == "solved" and len(outcome.members) > 1 and not by_few:
            self.run.add("grown window solved")  # by the window's full search
        if outcome.kind == "gave_up":
            self.run.add("window cap hit")
        if "descent moved" in self.run:
            self.run.add("descent then windows")

    def whole_component(self, outcome):
        if outcome.kind == "solved":
            self.run.add("whole component solved")

    def route(self, setting: str) -> Local:
        """The local route watched by this recorder: the default one, or a :data:`FORCED` one."""
        if setting == "default":
            return Local(observer=self)
        levels, descent = FORCED[setting]
        return Local(levels=levels, descent=descent, small_component=0, observer=self)

    def solve(self, monkeypatch, p, setting: str, **options):
        """``supcoord.solve(p, **options)`` on the default route or a :data:`FORCED` one
        (``monkeypatch``: accepted for the callers, nothing is patched); the verdict
        ``infeasible`` where no complete plan exists, as the oracle's distance is."""
        self.run = set()
        plan = solve(p, self.route(setting), **{"when_incomplete": "infeasible", **options})
        for how, kind in CERTIFICATES.items():
            if plan.status == "infeasible" and how in plan.reason:
                self.run.add(f"certificate: {kind}")
        self.kinds.update(self.run)
        return plan
