"""The demo scene's inks and a way to build their tables without `make tables` (tests, bench).

The same requests as `ink-tables build --ink <ink>` and as `ink="<ink>"` in a scene (every
default comes from `solver.table.request`); files named `<ink>.npz` like `make tables`.
"""

from __future__ import annotations

from pathlib import Path

DEMO_INKS = ("clear", "R30", "Y30", "B30", "G30", "Y25+B5")


def build_tables(folder, inks=DEMO_INKS, overwrite=True, **request_options) -> dict:
    """{ink: path} of the inks' tables written into `folder` (molecular: exact thin films)."""
    from solver.table import write_table
    from solver.table.builder import build_table
    from solver.table.request import table_request

    folder = Path(folder)
    paths = {}
    for ink in inks:
        path = folder / f"{ink}.npz"
        if overwrite or not path.is_file():
            write_table(path, build_table(table_request(ink, **request_options)))
        paths[ink] = path
    return paths


def main(argv=None) -> int:
    """`python -m inkbsdf.apps.demo_tables OUTDIR`: (re)build the demo tables that are missing,
    unreadable or not the current request's (their cache key differs: other settings, or code
    or data that changed the numbers since) — what `make tables` runs."""
    import sys

    from solver.table import TableError, read_table
    from solver.table.request import table_request

    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print("usage: python -m inkbsdf.apps.demo_tables OUTDIR", file=sys.stderr)
        return 2
    folder = Path(args[0])
    for ink in DEMO_INKS:
        path = folder / f"{ink}.npz"
        try:
            if read_table(path).meta.get("cache_key") == table_request(ink).key():
                continue
            print(f"rebuilding {path}: computed by other code, data or settings than today's request")
        except TableError as exc:
            if path.exists():
                print(f"rebuilding {path}: {exc}")
        build_tables(folder, [ink])
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
