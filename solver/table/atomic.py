"""Atomic file writes: a reader (or a build resumed after a kill) never sees a partial file."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import numpy as np


def _temp(path: Path) -> tuple[int, str]:
    """A temp file beside `path`, named <name>.<pid>.<random>.tmp so that a later sweep can tell
    whether its writer is still alive (solver/table/cache.py)."""
    return tempfile.mkstemp(prefix=f"{path.name}.{os.getpid()}.", suffix=".tmp", dir=path.parent)


def atomic_savez(path, arrays: dict, compressed: bool = False, durable: bool = True) -> Path:
    """np.savez to a temp file in the same folder, then rename over `path`.  durable: fsync
    before the rename (finished tables; a resumable build's parts skip it — a killed process
    loses nothing that was written, only a power cut could)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = _temp(path)
    try:
        with os.fdopen(fd, "wb") as fh:
            (np.savez_compressed if compressed else np.savez)(fh, **arrays)
            if durable:
                fh.flush()
                os.fsync(fh.fileno())
        _make_readable(Path(tmp))
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def _make_readable(path: Path) -> None:
    """mkstemp creates files 0600; give them the mode a plain open() would (0666 & ~umask),
    so that a cache or output folder shared by a team stays readable."""
    os.chmod(path, 0o666 & ~_umask())


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


def atomic_copy(source, path) -> Path:
    """Copy a file so that `path` is either absent/old or complete (temp file + rename)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = _temp(path)
    try:
        with os.fdopen(fd, "wb") as fh, open(source, "rb") as src:
            shutil.copyfileobj(src, fh)
            fh.flush()
            os.fsync(fh.fileno())
        _make_readable(Path(tmp))
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def atomic_write_text(path, text: str) -> Path:
    """Write a text file atomically (temp file + fsync + rename)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = _temp(path)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        _make_readable(Path(tmp))
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
