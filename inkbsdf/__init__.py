"""inkbsdf: a Mitsuba 3 BSDF for printed ink on paper (see README and docs/plugin.md).

`import inkbsdf` registers the `ink` BSDF for the active Mitsuba variant; when no variant is set
it first sets `cuda_ad_spectral` where a CUDA device exists, else `llvm_ad_spectral`. After
`mitsuba.set_variant(...)` call `inkbsdf.register()` again (Mitsuba's registry is per variant).
"""

import warnings

from .inks import InkSource, set_stack_provider, stack_provider
from .lut import InkLUT, load_lut
from .plugin import PLUGIN_NAME, register
from .variant import VariantError, check_variant, default_variant, ensure_variant

__all__ = ["InkLUT", "InkSource", "set_stack_provider", "stack_provider", "PLUGIN_NAME", "VariantError", "check_variant", "default_variant",
           "ensure_variant", "load_lut", "register"]

try:
    ensure_variant()
    register()
except VariantError as _exc:       # e.g. an RGB variant was active: say so, keep the import usable
    warnings.warn(f"inkbsdf: 'ink' BSDF not registered: {_exc}", stacklevel=2)
