"""inkbsdf: a Mitsuba 3 BSDF for printed ink on paper (see README and docs/plugin.md).

`import inkbsdf` sets no variant. It registers the `ink` BSDF for the active Mitsuba variant, if
one is set, and again whenever the variant changes (a `mitsuba.detail.add_variant_callback`
hook): `mi.set_variant(...)` before or after the import, then load scenes. `register()` does the
same by hand and returns the variant; `ensure_variant()` sets the default one
(`cuda_ad_spectral` where a CUDA device exists, else `llvm_ad_spectral`) when none is set.
"""

from .inks import InkSource, set_stack_provider, stack_provider
from .lut import InkLUT, load_lut
from .plugin import PLUGIN_NAME, follow_variant, register
from .variant import VariantError, check_variant, default_variant, ensure_variant

__all__ = ["InkLUT", "InkSource", "set_stack_provider", "stack_provider", "PLUGIN_NAME", "VariantError", "check_variant", "default_variant",
           "ensure_variant", "follow_variant", "load_lut", "register"]

follow_variant()
