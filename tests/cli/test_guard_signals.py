"""A command's work runs in a forked child (:mod:`supcoord.cli.guard`); when another process
or the system stops that child (SIGTERM, SIGKILL), the command says so in one line and exits
with the shell's status ``128 + signal``, not with "a bug (please report it)"."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest


def _children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux) to find the child")
@pytest.mark.timeout(120)
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["term", "kill"])
def test_a_child_stopped_from_outside_is_reported_as_such(sig):
    proc = subprocess.Popen([sys.executable, "-m", "supcoord.cli", "paper", "--positioners", "19", "--steps", "8",
                             "--model", "coupled", "--seed", "29", "--max-memory", "4G", "--timeout", "100"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 60
        while not (children := _children(proc.pid)):
            assert proc.poll() is None and time.monotonic() < deadline, "no forked child appeared"
            time.sleep(0.05)
        time.sleep(0.5)
        os.kill(children[0], sig)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    lines = err.decode().strip().splitlines()
    assert proc.returncode == 128 + sig, err.decode()
    assert len(lines) == 1 and f"stopped by {sig.name} from outside supcoord" in lines[0], lines
    assert "bug" not in lines[0] and "Traceback" not in err.decode()
