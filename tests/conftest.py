"""Suite-wide setup: compile the other integration loops on a second core.

A cold suite (a fresh clone, an empty kernel cache) spends most of its first minutes
compiling the default method's integration loop, which cannot be split. Meanwhile
`python -m clearance.warmup` compiles the loops of the other methods (dop853 / vern7,
rk4) and the post-processing in a process of its own, into the same on-disk cache, so the
tests that use them later load them instead of compiling them again. With a warm cache it
only loads them and exits within seconds. CLEARANCE_NO_WARMUP=1 turns it off (for
example on a single core, where it would only compete).
"""

from __future__ import annotations

import os
import subprocess
import sys

_warmup: subprocess.Popen | None = None


def pytest_configure(config) -> None:
    global _warmup
    if os.environ.get("CLEARANCE_NO_WARMUP") or (os.cpu_count() or 1) < 2:
        return
    if hasattr(config, "workerinput"):  # (a pytest-xdist worker: the controller started it)
        return
    _warmup = subprocess.Popen(
        [sys.executable, "-m", "clearance.warmup"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


def pytest_unconfigure(config) -> None:
    if _warmup is not None and _warmup.poll() is None:
        _warmup.terminate()
        try:
            _warmup.wait(timeout=10)
        except subprocess.TimeoutExpired:
            _warmup.kill()
