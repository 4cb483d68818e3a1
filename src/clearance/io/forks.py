"""Signals in the processes the package forks (figure drawing, cold compiles)."""

from __future__ import annotations

import signal


def forked_worker_signals() -> None:
    """First thing in a forked helper process: SIGTERM ends it, Ctrl-C is left to the parent.

    A fork inherits its parent's Python signal handlers, and `clearance run` turns SIGTERM
    into KeyboardInterrupt (a batch system's time limit stops it like Ctrl-C). In a helper
    that exception can arrive where the helper outlives it: a figure pool's `terminate()`
    then waited forever for a worker still blocked on the pool's task queue (seen in the
    test suite; a loop of fork pools with that handler hangs within a few hundred). With
    the default action the kernel ends the process wherever it is. Ctrl-C in a terminal
    reaches the whole process group: the helpers ignore it, and the parent, which decides
    what to keep, stops them."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
