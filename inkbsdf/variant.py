"""Which Mitsuba variant the plugin runs in: any of them. Spectral ones use the tables as they
are; RGB and mono ones get them reduced once at load to their colour channels
(`inkbsdf.colour_space`); polarized ones (`*_polarized`) make the mirror lobe a Mueller matrix
(`inkbsdf.polarized`).

`check_variant` is the one place that decides whether the ink BSDF supports a variant; the
others (`usable_variants`, `select_variant`, `bsdf_class` in plugin.py) ask it.
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi

DEFAULT_CPU_VARIANT = "llvm_ad_spectral"
DEFAULT_GPU_VARIANT = "cuda_ad_spectral"


class VariantError(RuntimeError):
    """The active Mitsuba variant cannot run the ink BSDF."""


def default_variant() -> str:
    """`cuda_ad_spectral` where a CUDA device is usable, else `llvm_ad_spectral`."""
    available = mi.variants()
    if DEFAULT_GPU_VARIANT in available and dr.has_backend(dr.JitBackend.CUDA):
        return DEFAULT_GPU_VARIANT
    return DEFAULT_CPU_VARIANT


def check_variant(variant: str | None) -> str:
    """Return the variant if the ink BSDF supports it (every Mitsuba variant), else raise
    VariantError saying why and what to do."""
    if variant is None:
        raise VariantError("no Mitsuba variant is set: call mitsuba.set_variant('llvm_ad_spectral') "
                           "(or 'cuda_ad_spectral', 'scalar_spectral', an RGB or mono variant) before "
                           "loading a scene with the ink BSDF")
    return variant


def _backend_present(variant: str) -> bool:
    if variant.startswith("cuda_"):
        return dr.has_backend(dr.JitBackend.CUDA)
    if variant.startswith("llvm_"):
        return dr.has_backend(dr.JitBackend.LLVM)
    return True


def usable_variants() -> list[str]:
    """Variants of this Mitsuba build that the ink BSDF supports and this machine can run."""
    usable = []
    for variant in mi.variants():
        try:
            check_variant(variant)
        except VariantError:
            continue
        if _backend_present(variant):
            usable.append(variant)
    return usable


def select_variant(name: str | None = None) -> str:
    """Set the named variant (None: `default_variant()`) and return it; VariantError naming the
    problem and the usable variants when the ink BSDF cannot run in it here."""
    variant = name or default_variant()
    usable = ", ".join(usable_variants()) or "none"
    if variant not in mi.variants():
        raise VariantError(f"'{variant}' is not a variant of this Mitsuba build; usable here: {usable}")
    check_variant(variant)
    if not _backend_present(variant):
        device = "a CUDA GPU" if variant.startswith("cuda_") else "Mitsuba's LLVM backend (libLLVM ≥ 16)"
        raise VariantError(f"'{variant}' needs {device}, which this machine lacks; usable here: {usable}")
    mi.set_variant(variant)
    return variant


def ensure_variant() -> str:
    """Keep the active variant, or set the default one if none is set; return it."""
    if mi.variant() is None:
        mi.set_variant(default_variant())
    return mi.variant()
