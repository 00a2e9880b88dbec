"""Content-addressed table cache with resumable partial results.

    <root>/tables/<key>.npz     finished tables (schema v1), <key>.json the request
    <root>/parts/<key>/*.npz    finished work units of a build in progress

Root: $INKBSDF_CACHE, else ~/.cache/inkbsdf.  Every write is atomic (temp file + rename), so
an interrupted build leaves only whole files; the next build reuses them and computes the rest.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shutil
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .atomic import atomic_savez
from .request import TableRequest
from .schema import InkTable, TableError, read_table


def default_root() -> Path:
    env = os.environ.get("INKBSDF_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "inkbsdf"


@dataclass(frozen=True)
class TableCache:
    root: Path

    @classmethod
    def default(cls) -> "TableCache":
        return cls(default_root())

    def table_path(self, request: TableRequest) -> Path:
        return self.root / "tables" / f"{request.key()}.npz"

    def parts_dir(self, request: TableRequest) -> Path:
        return self.root / "parts" / request.key()

    def load(self, request: TableRequest) -> InkTable | None:
        """The finished table, or None when absent (a corrupt entry is reported, not used)."""
        path = self.table_path(request)
        if not path.exists():
            return None
        try:
            return read_table(path)
        except TableError:
            path.unlink(missing_ok=True)         # rebuilt below; never serve a bad file
            return None

    def store(self, request: TableRequest, table: InkTable) -> Path:
        from .schema import write_table

        path = write_table(self.table_path(request), table)
        meta = self.table_path(request).with_suffix(".json")
        meta.write_text(json.dumps(request.numeric_fields(), indent=1, sort_keys=True))
        shutil.rmtree(self.parts_dir(request), ignore_errors=True)
        return path

    @contextlib.contextmanager
    def lock(self, request: TableRequest):
        """Exclusive lock on one table's build (flock: threads and processes alike)."""
        path = self.root / "locks" / f"{request.key()}.lock"
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "a") as fh:
            fcntl.flock(fh, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(fh, fcntl.LOCK_UN)

    # -- partial results of an unfinished build ---------------------------------------------
    def load_part(self, request: TableRequest, name: str) -> dict | None:
        path = self.parts_dir(request) / f"{name}.npz"
        if not path.exists():
            return None
        try:
            with np.load(path, allow_pickle=False) as npz:
                return {k: npz[k] for k in npz.files}
        except (zipfile.BadZipFile, EOFError, OSError, ValueError):
            path.unlink(missing_ok=True)
            return None

    def store_part(self, request: TableRequest, name: str, arrays: dict) -> None:
        atomic_savez(self.parts_dir(request) / f"{name}.npz", arrays, durable=False)
