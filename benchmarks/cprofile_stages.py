"""CPU time of a call split into named stages from a cProfile run (shared by the wave
benchmarks' child scripts, which run as plain scripts with an older solver on the path).

Stages by own time: (name, rules...), a rule (file suffix or "", function name or "*"):
"" matches any file (then the name is a substring of a built-in's name), "*" any function of
the file; an entry counts toward the first stage that matches.  Cumulative views:
(name, file suffix, function), summed over every match (they overlap the own-time stages).
"""
from __future__ import annotations

import cProfile
import pstats
import time


def matches(path: str, func: str, suffix: str, fname: str) -> bool:
    if not path.endswith(suffix):
        return False
    return fname == "*" or func == fname or (not suffix and fname in func)


def grouped_profile(fn, stages, cumulative) -> tuple[dict, dict, float]:
    """(own CPU s per stage, cumulative CPU s per view, total own CPU s) of one fn() call."""
    prof = cProfile.Profile(time.process_time)
    prof.enable()
    fn()
    prof.disable()
    own = {name: 0.0 for name, *_ in stages}
    cum = {name: 0.0 for name, *_ in cumulative}
    total = 0.0
    for (path, _, func), (_, _, tt, ct, _) in pstats.Stats(prof).stats.items():
        total += tt
        for name, *rules in stages:
            if any(matches(path, func, s, f) for s, f in rules):
                own[name] += tt
                break
        for name, suffix, fname in cumulative:
            if path.endswith(suffix) and func == fname:
                cum[name] += ct
    return own, cum, total
