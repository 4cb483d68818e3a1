"""Where numba caches the compiled kernels: one directory per version of the kernel sources.

numba validates a cached function against its own source file only. A kernel that calls
(and inlines) functions of other modules keeps running the old compiled code after one of
those modules changes: silently wrong results in a development tree. Here the cache
directory is keyed by a hash of every source file that can reach a kernel (all of the
package except the pure-Python layers in `_NO_KERNELS`), so any change to them starts a
fresh cache, and a cached kernel always matches the sources it was built from.

Location: $CLEARANCE_CACHE_DIR, else $NUMBA_CACHE_DIR, else $XDG_CACHE_HOME/clearance (or
~/.cache/clearance), then `numba-<numba version>-<hash>` (plus `-boundscheck`, `-opt<N>` or
`-debuginfo` when numba is configured so: its own cache key ignores them). Old directories
are left in place
(delete them freely). `configure()` sets numba's CACHE_DIR only while the package's kernel
modules are imported (the locator is fixed when a function is decorated), then restores
the previous value, so other numba users in the process are not affected.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numba
from numba.core import config

PACKAGE = Path(__file__).resolve().parent
# subpackages / modules without numba kernels that no kernel imports (editing them does not
# invalidate the cache); tests/test_kernel_cache.py checks both properties
_NO_KERNELS = (
    "analysis",
    "cli",
    "compile",
    "data",
    "io",
    "mechanisms",
    "model",
    "nonlinear",
    "parallel",
    "pipeline.py",
    "plot",
    "scenario",
    "store",
    "sweep",
    "view",
    "wear",
    "warmup.py",
)


def source_hash(root: Path = PACKAGE) -> str:
    """SHA-256 (16 hex digits) over the relative paths and contents of the kernel-reachable
    `.py` files under root."""
    h = hashlib.sha256()
    for p in sorted(root.rglob("*.py")):
        rel = p.relative_to(root)
        if rel.parts[0] in _NO_KERNELS:
            continue
        h.update(rel.as_posix().encode())
        h.update(b"\0")
        h.update(p.read_bytes())
        h.update(b"\0")
    return h.hexdigest()[:16]


def cache_dir(root: Path = PACKAGE) -> Path:
    base = os.environ.get("CLEARANCE_CACHE_DIR") or os.environ.get("NUMBA_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        base = str(Path(xdg) / "clearance")
    return Path(base) / f"numba-{numba.__version__}-{source_hash(root)}{_codegen_flags()}"


def _codegen_flags() -> str:
    """numba settings that change the compiled code but not numba's own cache key (which
    holds the signature, the CPU and the bytecode only): each gets its own directory, or
    NUMBA_BOUNDSCHECK=1 would load the unchecked kernels of an earlier run."""
    out = "-boundscheck" if config.BOUNDSCHECK else ""
    if int(config.OPT) != 3:
        out += f"-opt{int(config.OPT)}"
    if config.DEBUGINFO_DEFAULT:
        out += "-debuginfo"
    return out


def configure() -> str:
    """Point numba's cache at `cache_dir()`; return the previous CACHE_DIR for `restore`."""
    prev = config.CACHE_DIR
    config.CACHE_DIR = str(cache_dir())
    return prev


def restore(prev: str) -> None:
    config.CACHE_DIR = prev
