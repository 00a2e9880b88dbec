"""Vector Maxwell referee for the scalar wave solver (docs/vector_referee.md, docs/design.md §6).

treams (T-matrix multiple scattering, optional extra `vector`) solves periodic cells of
spheres in the binder slab; the same realizations go through `solver.wave`; the two are compared
in Rbar, Tbar, R_spec and in the colour of the ink on paper.  Entry point:
`python -m benchmarks.bench_vector`.

    oracles.py       Airy film (s, p) and Mie: closed forms the referee is checked against
    treams_layer.py  the vector model: sphere lattice → face-referenced slab S-matrix → faces
    cases.py         cases, their geometry (solver.geometry, face buffer), multipole order
    runs.py          one cached unit per (realization, λ, σ) for each solver
    compare.py       ensemble reduction, eq. (4) on paper, CIELAB, ΔE2000
    validate.py      the referee's checks and accuracy knobs
"""
