"""Mueller matrices of the `ink` BSDF in Mitsuba's polarized variants (docs/plugin.md,
"Polarized variants"; docs/design.md §1, §5).

    mirror lobe:  M = [[a, b, 0, 0], [b, a, 0, 0], [0, 0, C, −S], [0, 0, S, C]]
                  in the frame of the plane of incidence (Stokes basis vector = s direction),
                  a = Σ a_S R_spec,S, (b, C, S) = Σ a_S (b, C, S)_S (`inkbsdf.lut.mirror_mueller`),
                  the form of `mi.mueller.specular_reflection`; then rotated into Mitsuba's
                  implicit Stokes bases (`mi.mueller.stokes_basis`) of the incoming and the
                  outgoing ray, as Mitsuba's `conductor` and `dielectric` plugins do;
    smooth lobe:  value × ideal depolariser (`mi.mueller.depolarizer`): only M00 ≠ 0, which
                  no rotation of the frames changes.

Light arrives along −ŵo and leaves along +ŵi, with (ŵo, ŵi) = (wo, wi) in radiance transport
and (wi, wo) in importance transport (Mitsuba's convention for a BSDF's Mueller matrix in the
local shading frame; the integrator rotates it into world space).
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi


def mirror_matrix(a, b, c, s):
    """The mirror lobe's Mueller matrix (a mi.Spectrum of a polarized variant) from its elements
    (UnpolarizedSpectrum each), in the plane-of-incidence frame."""
    z = mi.UnpolarizedSpectrum(0.0)
    return mi.Spectrum(a, b, z, z,
                       b, a, z, z,
                       z, z, c, -s,
                       z, z, s, c)


def in_stokes_frames(m, wi, wo, mode):
    """`m` (plane-of-incidence frame) re-expressed between the implicit Stokes bases of the
    incoming and outgoing light (see the module docstring) with `mi.mueller.rotate_mueller_basis`.
    The reference vectors are Mitsuba's specular plugins': (0, 0, 1) × (−ŵo) in, (0, 0, 1) × ŵi
    out, normalised; (1, 0, 0) for both at normal incidence (no plane of incidence)."""
    wo_hat, wi_hat = (wo, wi) if mode == mi.TransportMode.Radiance else (wi, wo)
    n, x = mi.Vector3f(0, 0, 1), mi.Vector3f(1, 0, 0)
    s_in, s_out = dr.cross(n, -wo_hat), dr.cross(n, wi_hat)
    s_in = dr.normalize(dr.select(dr.squared_norm(s_in) == 0, x, s_in))     # no 0/0 anywhere
    s_out = dr.normalize(dr.select(dr.squared_norm(s_out) == 0, x, s_out))
    return mi.mueller.rotate_mueller_basis(m, -wo_hat, s_in, mi.mueller.stokes_basis(-wo_hat),
                                           wi_hat, s_out, mi.mueller.stokes_basis(wi_hat))


def depolarizing(value):
    """A smooth lobe's UnpolarizedSpectrum as the Mueller matrix of an ideal depolariser."""
    return mi.mueller.depolarizer(value)
