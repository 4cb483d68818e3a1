"""Atomic file writes: a file appears complete or not at all (never half written)."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to `path`; on success rename it over `path`.

    The temporary file lives in the same folder (so `os.replace` is atomic) and is removed
    if the body raises; an existing `path` is then left untouched. The final file gets the
    mode of the file it replaces, else 0o644.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        mode = path.stat().st_mode & 0o777 if path.exists() else 0o644
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


STEM_BYTES = 120  # UTF-8 bytes of a result file's stem: room for suffixes within 255
_UNSAFE = frozenset('/\\:*?"<>|')
_RESERVED = frozenset(
    ["CON", "PRN", "AUX", "NUL"] + [f"{p}{i}" for p in ("COM", "LPT") for i in range(1, 10)]
)


def output_stem(name: str) -> str:
    """The stem of the files named after a scenario or case `name`: the name itself when it
    is a safe file name (every shipped one is), else path separators, control characters and
    characters that Windows refuses replaced by '_', leading dots and spaces dropped (no
    '..', no hidden file), and at most STEM_BYTES bytes (a longer name keeps its start and
    gains an 8-character hash of the whole, so two long names stay apart; so does a name
    that had to be changed, so that 'a/b' and 'a_b' do not share a file). Results are
    therefore written inside their output folder, under a name the file system accepts."""
    import hashlib

    stem = "".join(
        "_" if ch in _UNSAFE or ord(ch) < 32 or 127 <= ord(ch) < 160 else ch for ch in str(name)
    )
    stem = stem.lstrip(". ").rstrip() or "scenario"
    if stem.split(".")[0].upper() in _RESERVED:  # names Windows keeps for devices
        stem = f"_{stem}"
    tag = hashlib.sha256(str(name).encode()).hexdigest()[:8]
    if len(stem.encode()) > STEM_BYTES:
        head = stem.encode()[: STEM_BYTES - 9].decode(errors="ignore")
        stem = f"{head}_{tag}"
    elif stem != str(name):  # changed: 'a/b' and 'a_b' must not share a file
        stem = f"{stem}_{tag}"
    return stem
