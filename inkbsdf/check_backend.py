"""Check that Mitsuba's LLVM backend works (libLLVM >= 16): `python -m inkbsdf.check_backend`."""

import sys


def main() -> int:
    try:
        import drjit as dr
        import mitsuba as mi

        mi.set_variant("llvm_ad_spectral")
        x = mi.Float([0.5, 2.0, 3.0])
        # dr.minimum compiles to llvm.minimum: LLVM 15 fails with "Cannot select: fminimum".
        y = dr.minimum(x, 1.0) + dr.maximum(x, 1.0)
        dr.eval(y)
        total = float(y.numpy().sum())
        if abs(total - 8.5) > 1e-5:
            raise RuntimeError(f"min/max kernel returned {total}, expected 8.5")
    except Exception as exc:  # pragma: no cover - message path
        print(f"ERROR: Mitsuba's LLVM backend does not work: {exc}\n"
              "       It needs libLLVM >= 16 (Debian 12: apt-get install libllvm19).",
              file=sys.stderr)
        return 1
    print("Mitsuba LLVM backend OK (llvm_ad_spectral)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
