"""Atomic file writes: a reader (or a build resumed after a kill) never sees a partial file.

Every writer goes through `atomic_file`: a temp file beside the target, named
<name>.<pid>.<random>.tmp (so a later sweep can tell whether its writer is still alive,
solver/table/cache.py), given the mode a plain open() would give, optionally fsynced, then
renamed over the target; on any exception (an interrupt included) the temp file is removed.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np


@contextlib.contextmanager
def atomic_file(path, mode: str = "wb", durable: bool = True):
    """Yield a file object whose content replaces `path` when the block ends without error.
    durable: fsync before the rename (finished tables; a resumable build's parts skip it — a
    killed process loses nothing that was written, only a power cut could)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f"{path.name}.{os.getpid()}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, mode, **({} if "b" in mode else {"encoding": "utf-8"})) as fh:
            yield fh
            if durable:
                fh.flush()
                os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())     # mkstemp makes 0600: keep a shared cache readable
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _umask() -> int:
    """The process umask, read without changing it where Linux allows (os.umask is not
    thread-safe: scene loads build tables from several threads)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_savez(path, arrays: dict, compressed: bool = False, durable: bool = True) -> Path:
    """np.savez(_compressed) to `path` atomically."""
    with atomic_file(path, "wb", durable) as fh:
        (np.savez_compressed if compressed else np.savez)(fh, **arrays)
    return Path(path)


def atomic_copy(source, path) -> Path:
    """Copy a file so that `path` is either absent/old or complete."""
    with atomic_file(path, "wb") as fh, open(source, "rb") as src:
        shutil.copyfileobj(src, fh)
    return Path(path)


def atomic_write_text(path, text: str) -> Path:
    """Write a text file atomically."""
    with atomic_file(path, "w") as fh:
        fh.write(text)
    return Path(path)
