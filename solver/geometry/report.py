"""Plain-text summary of a realization (CLI and benchmarks)."""

from __future__ import annotations

import numpy as np

from .statistics import cluster_statistic, find_overlaps, pair_correlation


def summary(real, vox=None) -> str:
    """Particle count, achieved fractions, packer statistics, structure statistics, grid volumes."""
    layer = real.layer
    st = real.stats
    lines = [f"layer {layer.label}  seed {real.seed}",
             f"particles {len(real.radii_nm)} ({real.shape}), effective diameter "
             + (f"{np.mean(real.effective_diameters_nm):.4g} nm" if len(real.radii_nm) else "-")
             + f", z range {real.z_range_nm[0]:.1f}..{real.z_range_nm[1]:.1f} nm"]
    target = dict(layer.ink.components)
    for code, achieved in real.achieved_fractions.items():
        count = int(np.sum(real.population == real.population_codes.index(code)))
        scale = dict(st.size_scale)[code]
        lines.append(f"  {code}: {count} grains, volume fraction {100 * achieved:.4f}% "
                     f"(target {100 * target[code]:.4g}%, sizes scaled by {scale:.5f})")
    lines.append(f"placement {st.method}: RSA {st.rsa_placed} placed in {st.rsa_tries} tries "
                 f"at size x{st.rsa_scale:.3f}; total {st.seconds:.2f} s")
    if st.pack is not None:
        p = st.pack
        lines.append(f"packer: {p.iterations} iterations, {p.rebuilds} neighbour-list builds, "
                     f"converged {p.converged}, {p.seconds:.2f} s")
    if st.agglutination is not None:
        a = st.agglutination
        lines.append(f"agglutination: {a.strength_kT:g} kT, {a.steps} Brownian steps, {a.seconds:.2f} s")
    if real.shape.oriented and len(real.axes):
        lines.append(f"orientation: <|a_z|> = {np.mean(np.abs(real.axes[:, 2])):.3f} "
                     "(isotropic 0.5, in-plane 0, vertical 1)")
    lines.append(f"overlapping pairs: {len(find_overlaps(real))}")
    cs = cluster_statistic(real)
    lines.append(f"clusters (gap < {cs.bond_gap_nm:.3g} nm): mean size seen by a grain {cs.mean_cluster_size:.2f}, "
                 f"largest {100 * cs.largest_cluster_fraction:.1f}% of grains, "
                 f"{cs.bonds_per_particle:.2f} bonds per grain")
    if len(real.radii_nm) > 1:
        d = float(np.mean(real.effective_diameters_nm))
        r, g = pair_correlation(real, min(3.0 * d, 0.45 * min(real.period_nm)), bins=30)
        lines.append(f"pair correlation: max g(r) = {g.max():.2f} at r = {r[np.argmax(g)]:.0f} nm")
    if vox is not None:
        pig = sum(vox.volume_nm3(c) for c in real.population_codes)
        exact = float(np.sum(real.volumes_nm3))
        lines.append(f"voxel grid {'×'.join(map(str, vox.shape))} ({vox.lines_per_voxel}×{vox.lines_per_voxel} lines per column): "
                     f"pigment volume / particle volume - 1 = {pig / exact - 1 if exact else 0.0:+.2e}")
    return "\n".join(lines)
