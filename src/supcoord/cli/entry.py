"""The ``supcoord`` console script: Ctrl-C is clean from the first instruction.

Until the command starts working (importing numpy, dd and the commands, parsing the
arguments), an interrupt ends the process at once with one line and exit status 130,
instead of a ``KeyboardInterrupt`` traceback from whatever module was being imported.
:func:`supcoord.cli.main.main` then takes over (the first interrupt stops the work
cleanly, later ones are ignored while it cleans up).
"""

import os
import signal
import sys
import threading


def _interrupted(signum, frame):  # noqa: ARG001
    os.write(2, b"supcoord: interrupted\n")
    os._exit(130)


def main() -> int:
    """Install the start-up interrupt handler, then run :func:`supcoord.cli.main.main`.

    After an interrupt the process leaves at once (``os._exit(130)`` once the output is
    flushed): the interpreter's shutdown (freeing a large BDD manager can take seconds)
    restores the default handler, so a second Ctrl-C there would kill it by signal."""
    main_thread = threading.current_thread() is threading.main_thread()
    if main_thread:
        signal.signal(signal.SIGINT, _interrupted)
    from .main import main as run

    code = run()
    if main_thread:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # the result is out: nothing left to interrupt
    if code == 130:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(130)
    return code


if __name__ == "__main__":
    sys.exit(main())
