"""The jackknife over a wave table's realizations: leave-one-out ensembles and the standard error
of anything computed from them (docs/figures.md, "The colour's standard error").

A wave table is the mean of N random realizations.  Its leave-one-out ensemble k is the same
reduction (and refinement) of the realizations r ≠ k; the table stores, per replica k, the
columns a colour reads (schema.JACKKNIFE_COLUMNS, as `<name>_jack`).  For any quantity c
computed from the table — however nonlinearly, e.g. CIELAB — with c_k the same computation on
replica k,

    SE²(c) = (N − 1)/N · Σ_k (c_k − c̄)²,   c̄ = mean_k c_k,

with N − 1 degrees of freedom.  For a mean (c linear in the realizations) this is exactly the
standard error of the mean, s/√N; the correlations between the nodes of the table (the same
cells at every λ and σ) are in the replicas, so nothing about them has to be assumed.
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Sequence, TypeVar

import numpy as np

from .schema import JACKKNIFE_COLUMNS, JACKKNIFE_DTYPE, InkTable

T = TypeVar("T")


def leave_one_out(items: Sequence[T]) -> list[list[T]]:
    """[all but item k for k = 0 … N−1] (N ≥ 2)."""
    items = list(items)
    if len(items) < 2:
        raise ValueError(f"a jackknife needs at least 2 realizations, got {len(items)}")
    return [items[:k] + items[k + 1:] for k in range(len(items))]


def attach(table: InkTable, replicas: Sequence[InkTable]) -> InkTable:
    """`table` holding the JACKKNIFE_COLUMNS of its leave-one-out tables `replicas` (on its grids),
    and R's standard error taken from them: the replicas went through the same normal-incidence
    average, reciprocity and refinement as R, where the per-node spread of the reduction did not
    (it put 0.35–0.6 on grazing nodes where R is 0); stratified by the table's meta
    `jackknife_groups` where it has them."""
    if len(replicas) < 2:
        raise ValueError(f"a jackknife needs at least 2 leave-one-out tables, got {len(replicas)}")
    jack = {name: np.stack([r.column(name) for r in replicas]).astype(JACKKNIFE_DTYPE) for name in JACKKNIFE_COLUMNS}
    errors = dict(table.errors)
    if errors:                                  # a table with standard errors: R's from its replicas
        errors["R"] = standard_error(jack["R"], table.meta.get("jackknife_groups"))
    return dataclasses.replace(table, jackknife=jack, errors=errors)


def count(table: InkTable) -> int:
    """The number of leave-one-out ensembles a table holds (0: none)."""
    return 0 if table.jackknife is None else next(iter(table.jackknife.values())).shape[0]


def reduce_with_replicas(reduce: Callable[[list], InkTable], realizations: Sequence) -> InkTable:
    """reduce(realizations), holding the columns of reduce(each leave-one-out subset) when there
    are ≥ 2 realizations: one function makes the table and its replicas alike (the ensemble
    average and any refinement after it)."""
    table = reduce(list(realizations))
    if len(realizations) < 2:
        return table
    return attach(table, [reduce(rest) for rest in leave_one_out(realizations)])


def replicas(table: InkTable) -> list[dict] | None:
    """Per leave-one-out ensemble, its columns as float64 ({name: array}); None without jackknife."""
    if table.jackknife is None:
        return None
    return [{name: np.asarray(a[k], dtype=np.float64) for name, a in table.jackknife.items()}
            for k in range(count(table))]


def standard_error(values, groups: Sequence[int] | None = None) -> np.ndarray:
    """The jackknife standard error from the leave-one-out values (axis 0: the N ≥ 2 replicas):
    sqrt((N − 1)/N · Σ_k (c_k − c̄)²), per remaining component.

    groups: the stratum of each replica's left-out realization where the realizations form
    independent groups (TE and TM cells alternating: wave_tier.alternates; the table's meta
    `jackknife_groups`): then the stratified jackknife Σ_g (n_g − 1)/n_g Σ_{k∈g} (c_k − c̄_g)²,
    exact for a mean of group means (the pooled form overstates it by up to (N−1)/N · n_g/(n_g−1)),
    with N − G degrees of freedom (`degrees_of_freedom`)."""
    values = np.asarray(values, dtype=np.float64)
    n = values.shape[0]
    if n < 2:
        raise ValueError(f"a jackknife needs at least 2 leave-one-out values, got {n}")
    if groups is None or len(set(groups)) < 2:
        return np.sqrt((n - 1) / n * np.sum((values - values.mean(axis=0)) ** 2, axis=0))
    groups = np.asarray(groups)
    if groups.shape != (n,) or min(np.count_nonzero(groups == g) for g in set(groups.tolist())) < 2:
        raise ValueError(f"jackknife groups {groups.tolist()}: one per replica, each group ≥ 2")
    var = 0.0
    for g in set(groups.tolist()):
        v = values[groups == g]
        var = var + (v.shape[0] - 1) / v.shape[0] * np.sum((v - v.mean(axis=0)) ** 2, axis=0)
    return np.sqrt(var)


def degrees_of_freedom(count: int, groups: Sequence[int] | None = None) -> int:
    """N − 1, or N − G for G independent groups (standard_error)."""
    return count - (1 if groups is None else max(1, len(set(groups))))
