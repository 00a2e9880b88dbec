"""Which Mitsuba variant the plugin runs in: spectral, unpolarized or polarized
(`*_spectral_polarized`: the mirror lobe is a Mueller matrix, inkbsdf/polarized.py).

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


def _counterpart(variant: str) -> str:
    """The spectral variant on the same backend, polarized if `variant` is:
    llvm_ad_rgb → llvm_ad_spectral, llvm_ad_mono_polarized → llvm_ad_spectral_polarized."""
    backend = variant.split("_ad_")[0] + "_ad" if "_ad_" in variant else variant.split("_")[0]
    return f"{backend}_spectral" + ("_polarized" if variant.endswith("_polarized") else "")


def check_variant(variant: str | None) -> str:
    """Return the variant if the ink BSDF supports it, else raise VariantError saying why and
    which variant to use instead."""
    if variant is None:
        raise VariantError("no Mitsuba variant is set: call mitsuba.set_variant('llvm_ad_spectral') "
                           "(or 'cuda_ad_spectral', 'scalar_spectral') before inkbsdf.register()")
    if "spectral" not in variant:
        raise VariantError(f"the ink BSDF needs a spectral Mitsuba variant, the active one is "
                           f"'{variant}': an RGB or mono variant would give wrong colours "
                           f"(use '{_counterpart(variant)}')")
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
    usable = ", ".join(usable_variants()) or "none (this Mitsuba build has no spectral variant)"
    if variant not in mi.variants():
        raise VariantError(f"'{variant}' is not a variant of this Mitsuba build; the ink BSDF runs in: {usable}")
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
