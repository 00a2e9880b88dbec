"""Content-addressed table cache with resumable partial results.

    <root>/tables/<key>.npz     finished tables, <key>.json the request that made them
    <root>/parts/<key>/*.npz    finished work units of a build in progress
    <root>/locks/<key>.lock     one builder per table (flock)
    <root>/geometry/<key>.npz   voxel fractions of one realization, shared by every table whose
                                grains are the same (geometry_store.py)

Root: $INKBSDF_CACHE, else ~/.cache/inkbsdf.  A cache that cannot be written (a shared,
read-only folder) serves the tables it holds; only a build needs it writable.  Every write is atomic (temp file + rename), so
an interrupted build leaves only whole files; the next build reuses them and computes the rest.
A part that cannot be read or holds non-finite numbers is logged by name, removed and
recomputed.  Temp files of writers that died (their pid is in the name), parts of builds
abandoned and geometry unused for PARTS_MAX_AGE_DAYS are swept when a build starts.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import json
import logging
import os
import shutil
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .atomic import atomic_savez, atomic_write_text
from .request import TableRequest
from .schema import InkTable, TableError, read_table

log = logging.getLogger("inkbsdf.tables")
PARTS_MAX_AGE_DAYS = 30.0


class CacheError(ValueError):
    """The cache folder cannot be used; the message names it and the fix."""


def default_root() -> Path:
    env = os.environ.get("INKBSDF_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "inkbsdf"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


@dataclass(frozen=True)
class TableCache:
    root: Path

    def __post_init__(self):
        object.__setattr__(self, "root", Path(self.root).expanduser())

    @classmethod
    def default(cls) -> "TableCache":
        return cls(default_root())

    def table_path(self, request: TableRequest) -> Path:
        return self.root / "tables" / f"{request.key()}.npz"

    def parts_dir(self, request: TableRequest) -> Path:
        return self.root / "parts" / request.key()

    def check(self) -> None:
        """Create the cache's folders or say in one line why they cannot be used."""
        where = "$INKBSDF_CACHE" if os.environ.get("INKBSDF_CACHE") and self.root == default_root() else "cache"
        if self.root.exists() and not self.root.is_dir():
            raise CacheError(f"{where} {self.root} is a file, not a folder: point it at a folder")
        try:
            for sub in ("tables", "parts", "locks", "geometry"):
                (self.root / sub).mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            what = "is not writable" if self.root.is_dir() else "cannot be created"
            # a folder that exists and reads still serves its tables; one that does not exist, nothing
            served = " (its tables are still served)" if self.root.is_dir() and os.access(self.root, os.R_OK | os.X_OK) \
                else ""
            raise CacheError(f"{where} {self.root} {what} ({exc.strerror}), and building a table needs to write "
                             f"to it{served}: choose a writable folder with --cache or $INKBSDF_CACHE") from None
        if not os.access(self.root / "tables", os.W_OK | os.X_OK):
            raise CacheError(f"{where} {self.root} is not writable: choose a writable folder with --cache "
                             "or $INKBSDF_CACHE")

    def sweep(self) -> None:
        """Remove temp files of dead writers and parts of builds abandoned long ago."""
        for tmp in (list(self.root.glob("tables/*.tmp")) + list(self.root.glob("parts/*/*.tmp"))
                    + list(self.root.glob("geometry/*.tmp"))):
            try:
                pid = int(tmp.name.rsplit(".", 3)[-3])
            except (ValueError, IndexError):
                continue
            if not _pid_alive(pid):
                tmp.unlink(missing_ok=True)
        cutoff = time.time() - PARTS_MAX_AGE_DAYS * 86400.0
        for folder in self.root.glob("parts/*"):
            try:
                newest = max([folder.stat().st_mtime] + [p.stat().st_mtime for p in folder.iterdir()])
            except OSError:
                continue
            if newest < cutoff:
                log.info("removing parts of a build abandoned %.0f days ago: %s",
                         (time.time() - newest) / 86400.0, folder)
                shutil.rmtree(folder, ignore_errors=True)
        for path in self.root.glob("geometry/*.npz"):          # read refreshes the mtime
            with contextlib.suppress(OSError):
                if path.stat().st_mtime < cutoff:
                    path.unlink()

    def load(self, request: TableRequest) -> InkTable | None:
        """The finished table, or None when absent (a corrupt entry is removed, never served)."""
        path = self.table_path(request)
        if not path.exists():
            return None
        try:
            return read_table(path)
        except TableError as exc:
            log.warning("cached table unusable, rebuilding it: %s", exc)
            with contextlib.suppress(OSError):  # a read-only cache: `check` refuses it before a build
                path.unlink(missing_ok=True)
            return None

    def store(self, request: TableRequest, table: InkTable) -> Path:
        from .schema import write_table

        path = write_table(self.table_path(request), table)
        atomic_write_text(path.with_suffix(".json"),
                          json.dumps(request.numeric_fields(), indent=1, sort_keys=True, allow_nan=False))
        shutil.rmtree(self.parts_dir(request), ignore_errors=True)
        return path

    @contextlib.contextmanager
    def lock(self, request: TableRequest):
        """Exclusive lock on one table's build (flock: threads and processes alike); says so
        when it has to wait for another builder."""
        path = self.root / "locks" / f"{request.key()}.lock"
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "a") as fh:
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as exc:
                if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN):
                    raise
                log.info("waiting for another process that is building %s (lock %s)", request.describe(), path)
                fcntl.flock(fh, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(fh, fcntl.LOCK_UN)

    # -- partial results of an unfinished build ---------------------------------------------
    def load_part(self, request: TableRequest, name: str) -> dict | None:
        """A stored unit result, or None (absent, unreadable or non-finite: removed, recomputed)."""
        return _load_arrays(self.parts_dir(request) / f"{name}.npz")

    def store_part(self, request: TableRequest, name: str, arrays: dict) -> None:
        atomic_savez(self.parts_dir(request) / f"{name}.npz", arrays, durable=False)

    # -- geometry shared between tables (geometry_store.py) --------------------------------
    def geometry_path(self, key: str) -> Path:
        return self.root / "geometry" / f"{key}.npz"

    def load_geometry(self, key: str) -> dict | None:
        """A realization's stored voxel fractions, or None; a read keeps it from the sweep."""
        path = self.geometry_path(key)
        arrays = _load_arrays(path)
        if arrays is not None:
            with contextlib.suppress(OSError):      # a read-only cache still serves it
                os.utime(path)
        return arrays

    def has_geometry(self, key: str) -> bool:
        return self.geometry_path(key).exists()

    def store_geometry(self, key: str, arrays: dict) -> None:
        """Compressed: the fractions are mostly 0 and 1 (a 48×48×24 realization ~0.7 MB raw)."""
        atomic_savez(self.geometry_path(key), arrays, compressed=True, durable=False)


def _load_arrays(path: Path) -> dict | None:
    """The arrays of a stored npz, or None (absent, unreadable or non-finite: removed)."""
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (zipfile.BadZipFile, EOFError, OSError, ValueError) as exc:
        log.warning("unreadable part %s (%s): recomputing it", path, exc)
        path.unlink(missing_ok=True)
        return None
    bad = [k for k, v in arrays.items() if v.dtype.kind in "fc" and not np.all(np.isfinite(v))]
    if bad:
        log.warning("part %s holds non-finite values in %s: recomputing it", path, ", ".join(bad))
        path.unlink(missing_ok=True)
        return None
    return arrays
