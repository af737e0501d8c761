"""What one ``solve`` does on the window route, recorded for the tests that compare it with the
independent oracle (``test_planner_oracle.py``, ``test_exact_oracle.py``): the window searches,
the descents, the certificate's reason — wrapped, not changed — and the forced window settings."""

from __future__ import annotations

from collections import Counter

from supcoord.planning import planner, solve, windows

#: the window route forced: (levels, greedy)
FORCED = {
    "windows A": ((18, 60, 200, None), True),
    "windows B": ((12, 40, 135, None), False),
    "windows C": ((30, 300, None), True),
    "windows D": ((30, 300, None), False),
}
CERTIFICATES = {"their conflict component": "conflict component", "this relaxed subproblem": "relaxed subproblem",
                "no other positioner restricts them": "no blocker"}


class Recorder:
    """Counts what one ``solve`` does in the window route (wrapped, not changed)."""

    def __init__(self, monkeypatch):
        self.kinds: Counter = Counter()
        self.run: set[str] = set()
        self.few_solved = 0
        grow, whole, descent = windows._Windows.grow, windows._Windows.whole, windows.descent
        few = windows._Windows._few_displaced

        def rec_few(win, *args):
            out = few(win, *args)
            if out is not None:
                self.run.add("few-displaced window solved")
                self.few_solved += 1
            return out

        def rec_grow(win, p, c, done, comp, cap):
            before = self.few_solved
            out = grow(win, p, c, done, comp, cap)
            self.run.add("window")
            if out.kind == "solved" and len(out.members) > 1 and self.few_solved == before:
                self.run.add("grown window solved")  # by the window's full search
            if out.kind == "gave_up":
                self.run.add("window cap hit")
            if "descent moved" in self.run:
                self.run.add("descent then windows")
            return out

        def rec_whole(win, comp, c):
            out = whole(win, comp, c)
            if out.kind == "solved":
                self.run.add("whole component solved")
            return out

        def rec_descent(problem, c, check=None):
            steps, end = descent(problem, c, check=check)
            if steps:
                self.run.add("descent moved")
            return steps, end

        monkeypatch.setattr(windows._Windows, "grow", rec_grow)
        monkeypatch.setattr(windows._Windows, "whole", rec_whole)
        monkeypatch.setattr(windows._Windows, "_few_displaced", rec_few)
        monkeypatch.setattr(windows, "descent", rec_descent)
        monkeypatch.setattr(planner, "descent", rec_descent)  # the first descents choose the direction

    def solve(self, monkeypatch, p, setting: str, **options):
        """``supcoord.solve(p, **options)`` on the default route or a :data:`FORCED` one."""
        self.run = set()
        if setting == "default":
            plan = solve(p, **options)
        else:
            levels, greedy = FORCED[setting]
            with monkeypatch.context() as m:
                m.setattr(windows, "SMALL_COMPONENT", 0)
                plan = solve(p, levels=levels, greedy=greedy, **options)
        for how, kind in CERTIFICATES.items():
            if plan.status == "infeasible" and how in plan.reason:
                self.run.add(f"certificate: {kind}")
        self.kinds.update(self.run)
        return plan
