"""The process ink set — black, cyan, magenta, yellow, in printing order — designed against
ISO 12647-2 PC1 (docs/printing.md "Process inks").

The recipes are package data (`solver/data/process_inks.json`), the output of the command it
records (`ink-tables design --aim iso12647-2 -o …`): rerun that command to remake them. Each ink
is a molecular ink spec and its layer thickness, for `table_request(spec, thickness_nm=…)`;
the paper is the flat albedo designed against the PC1 paper white.

    for ink in process_inks():          # K, C, M, Y
        request = table_request(ink.spec, thickness_nm=ink.thickness_nm)
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

from ..colour.aims import PROCESS_ORDER


@dataclass(frozen=True)
class ProcessInk:
    colour: str                  # black, cyan, magenta, yellow
    spec: str                    # molecular ink spec, e.g. "C8.6983"
    thickness_nm: float
    lab: tuple[float, float, float]      # its solid on the process paper (45:0, D50, 2°), as designed
    aim: tuple[float, float, float]      # the standard's


@lru_cache(maxsize=1)
def _document() -> dict:
    return json.loads(resources.files("solver.data").joinpath("process_inks.json").read_text())


def process_inks() -> tuple[ProcessInk, ...]:
    """The four process inks in printing order (K, C, M, Y)."""
    aims = _document()["aims"]
    return tuple(ProcessInk(c, aims[c]["recipe"]["ink"], float(aims[c]["recipe"]["thickness_nm"]),
                            tuple(aims[c]["lab"]), tuple(aims[c]["aim"])) for c in PROCESS_ORDER)


def process_paper_albedo() -> float:
    """The paper albedo the set was designed on (the PC1 paper white's flat albedo)."""
    return float(_document()["aims"]["paper"]["recipe"]["paper_albedo"])


def process_command() -> str:
    """The command that made the data."""
    return _document()["command"]
