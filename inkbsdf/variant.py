"""Which Mitsuba variant the plugin runs in: spectral, unpolarized."""

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
    """Return the variant if the ink BSDF supports it, else raise VariantError saying why."""
    if variant is None:
        raise VariantError("no Mitsuba variant is set: call mitsuba.set_variant('llvm_ad_spectral') "
                           "(or 'cuda_ad_spectral', 'scalar_spectral') before inkbsdf.register()")
    if "spectral" not in variant:
        raise VariantError(f"the ink BSDF needs a spectral Mitsuba variant, the active one is "
                           f"'{variant}': an RGB or mono variant would give wrong colours "
                           f"(use e.g. '{DEFAULT_CPU_VARIANT}')")
    if "polarized" in variant:
        raise VariantError(f"the ink BSDF is unpolarized, the active variant is '{variant}' "
                           f"(use '{variant.replace('_polarized', '')}')")
    return variant


def ensure_variant() -> str:
    """Keep the active variant, or set the default one if none is set; return it."""
    if mi.variant() is None:
        mi.set_variant(default_variant())
    return mi.variant()
