"""The `ink` BSDF: a Mitsuba 3 plugin for printed ink on paper (docs/design.md §1, docs/plugin.md).

One ink (`filename` | `ink`, `coverage`) or up to four printed in order (`filename1` | `ink1`,
`coverage1`, …), mixed by coverage with Demichel weights over the printed primaries and the
`coverage_model` (Clapper–Yule by default, or Murray–Davies): `inkbsdf.mixing`.

Components: 0 = coherent specular reflection of the layers (a delta lobe, Σ a_S R_spec,S(σ)),
1 = everything smooth (diffuse layer lobes, light through the layers to the paper and back, bare
paper). Front side only (wrap in `twosided` for both faces). Every variant: RGB and mono ones
get the tables reduced to their channels (`inkbsdf.colour_space`). In the polarized ones the
delta lobe is the Mueller matrix of the mirror beams, built from the tables' s and p amplitudes,
and the smooth lobe depolarises (`inkbsdf.polarized`); tables without r_s, r_p are refused there.

Sampling picks the delta lobe with probability P_spec = mean_λ(specular)/mean_λ(total albedo)
per lane and otherwise samples the cosine-weighted hemisphere; `pdf` and `eval` cover component
1 only, honouring the context's component and type flags.
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
import numpy as np

from solver.paper import PAPER_ALBEDO, albedo_problem
from solver.printing import DEFAULT_COVERAGE_MODEL, check_coverage_model, possible_primaries, stack_order
from solver.table import TableError
from .colour_space import channel_coordinates, colour_space, reduce_lut
from .coverage import check_coverage_texture, coverage_support
from .errors import InkParameterError, plugin_factory
from .inks import load_inks, numbered_inks, stack_lut
from .mixing import LoopedPrint, PrintModel
from .model import InkModel, safe_div
from .premix import common_grid, premixed_lut
from .source import scene_param
from .polarized import depolarizing, in_stokes_frames, mirror_matrix
from .variant import check_variant

PLUGIN_NAME = "ink"
DEFAULT_COVERAGE = 1.0
SPECULAR, DIFFUSE = 0, 1            # component indices
#: distance |ωo − mirror(ωi)| (≈ angle, radians) within which eval/eval_pdf, while derivatives
#: are tracked, stand for the delta lobe (`_with_mirror_derivative`): 1000× the float32
#: round-off of a direction taken to world space and back, 1e-6 of the cosine lobe's samples
MIRROR_TOLERANCE = 1e-3

_classes: dict[str, type] = {}      # variant → BSDF class (a class derives from one variant's BSDF)
_models: dict[tuple, tuple] = {}    # (variant, id(lut)) → (lut, InkModel): one copy per table
_premixed: dict[tuple, tuple] = {}  # premixed and stacked tables: key → (tables, InkModel)
_MAX_MODELS = 64


def _clamp01(x):
    x = dr.select(x > 0, x, 0.0)    # selects, not dr.clip: no NaN propagation
    return dr.select(x < 1, x, 1.0)


def check_paper(texture) -> None:
    """InkParameterError when the paper albedo, a float or a spectrum (RGB included: anything
    not spatially varying), has a value outside [0, 1] over 360–830 nm, sampled every nm (a
    typo such as 9 for 0.9 would otherwise be clamped unseen).

    A spatially varying texture (a bitmap, …) is not read here, which would cost a pass over its
    data at every load: its values are still clamped per lookup (`_incident`), as are values set
    later through `mi.traverse`."""
    if texture.is_spatially_varying():
        return
    values = spectrum_values(texture)
    got = albedo_problem(float(values.min()), float(values.max()))
    if got is None:
        return
    raise InkParameterError(f"ink BSDF: parameter 'paper' is an albedo and must lie in [0, 1], {got}: "
                            'correct it (e.g. <float name="paper" value="0.9"/>, or the <default> that sets it)')


def spectrum_values(texture, n_groups: int = 118) -> np.ndarray:
    """A texture that is not spatially varying, evaluated at 4·`n_groups` wavelengths evenly
    spread over [MI_CIE_MIN, MI_CIE_MAX] nm (about 1 nm apart by default); its channels in RGB
    and mono variants."""
    if not mi.is_spectral:              # RGB and mono variants: the texture's channels
        si = dr.zeros(mi.SurfaceInteraction3f, 1) if dr.is_jit_v(mi.Float) else dr.zeros(mi.SurfaceInteraction3f)
        value = texture.eval(si)
        return np.array([float(np.ravel(np.asarray(value[j]))[0]) for j in range(dr.size_v(value))]
                        if dr.size_v(value) > 0 else [float(np.ravel(np.asarray(value))[0])])
    groups = np.linspace(mi.MI_CIE_MIN, mi.MI_CIE_MAX, 4 * n_groups).reshape(n_groups, 4)
    if dr.is_jit_v(mi.Float):           # one evaluation over n_groups lanes
        si = dr.zeros(mi.SurfaceInteraction3f, n_groups)
        si.wavelengths = mi.UnpolarizedSpectrum(*[mi.Float(column) for column in groups.T])
        return np.concatenate([np.ravel(np.asarray(c)) for c in texture.eval(si)])
    out = []
    for group in groups:                # scalar variants: one lane at a time
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wavelengths = mi.UnpolarizedSpectrum(*group)
        out.extend(float(c) for c in texture.eval(si))
    return np.asarray(out)


def _lobes(ctx):
    """(specular enabled, diffuse enabled) for this context."""
    return (ctx.is_enabled(mi.BSDFFlags.DeltaReflection, SPECULAR),
            ctx.is_enabled(mi.BSDFFlags.DiffuseReflection, DIFFUSE))


def _smooth(value):
    """The smooth lobe's value as this variant's Spectrum: a depolarising Mueller matrix in
    polarized variants."""
    return depolarizing(value) if mi.is_polarized else value


def check_polarizable(lut) -> None:
    """TableError unless `lut` has the s and p amplitudes a polarized variant needs."""
    if lut.mirror_sp is None:
        raise TableError(
            f"ink BSDF: {lut.source}: the polarized variant '{mi.variant()}' needs the mirror beam's "
            f"s and p amplitudes (r_s, r_p), and this table (polarisation '{lut.polarisation}') has "
            "none: use a table built with polarisation 'unpolarised', or an unpolarized variant "
            f"('{mi.variant().replace('_polarized', '')}')")


def model_for(lut):
    """The Dr.Jit tables of `lut` for the active variant (reduced to its colour channels in RGB
    and mono variants: `inkbsdf.colour_space`), shared by every BSDF using it."""
    key = (mi.variant(), id(lut))
    hit = _models.get(key)
    if hit is None or hit[0] is not lut:
        while len(_models) >= _MAX_MODELS:
            _models.pop(next(iter(_models)))
        hit = _models[key] = (lut, InkModel(reduce_lut(lut, colour_space())))
    return hit[1]


def premixed_model(coverages, primaries):
    """The InkModel of a uniform print's premixed table (`inkbsdf.premix`), or None; shared by
    every BSDF of this variant with the same tables and coverages (a scene of many shapes with
    one ink holds one copy)."""
    luts = tuple(lut for _, lut in primaries)
    key = (mi.variant(), tuple(float(c) for c in coverages), tuple(tuple(s) for s, _ in primaries),
           tuple(id(lut) for lut in luts))
    hit = _premixed.get(key)
    if hit is None or any(a is not b for a, b in zip(hit[0], luts)):
        lut = premixed_lut(coverages, primaries)
        if lut is None:
            return None
        while len(_premixed) >= _MAX_MODELS:
            _premixed.pop(next(iter(_premixed)))
        hit = _premixed[key] = (luts, InkModel(lut))
    return hit[1]


def stacked_model(luts):
    """The InkModel of `luts` stacked on their common grid (`LoopedPrint`), or None when they
    have none; shared by every BSDF of this variant with the same tables."""
    key = (mi.variant(), "stacked", tuple(id(lut) for lut in luts))
    hit = _premixed.get(key)
    if hit is None or any(a is not b for a, b in zip(hit[0], luts)):
        common = common_grid(list(luts))
        if common is None:
            return None
        while len(_premixed) >= _MAX_MODELS:
            _premixed.pop(next(iter(_premixed)))
        hit = _premixed[key] = (tuple(luts), InkModel.stacked(common))
    return hit[1]


def coverage_names(props) -> list[str]:
    """`coverage` for the single-ink form, `coverage1` … `coveragek` for k numbered inks."""
    numbers = numbered_inks(props)
    return [f"coverage{n}" for n in numbers] if numbers else ["coverage"]


def _define_class():
    class InkBSDF(mi.BSDF):
        def __init__(self, props):
            # Every check and table first, mi.BSDF.__init__ last: the C++ base puts the object in
            # Dr.Jit's BSDF registry of the variant, and a later render's symbolic calls traverse
            # and call every registered BSDF. A refused object (kept alive by its exception's
            # reference cycles until the garbage collector runs) must never be registered, or
            # those calls meet its missing attributes ('no attribute premixed').
            model = scene_param(props, "coverage_model", DEFAULT_COVERAGE_MODEL)
            try:
                self.coverage_model = check_coverage_model(model)
            except ValueError as exc:
                raise InkParameterError(f"ink BSDF: {exc}") from None
            self.paper = props.get_texture("paper", PAPER_ALBEDO)
            check_paper(self.paper)                 # before any table is read or built
            self.coverage_names = coverage_names(props)
            self.inks = load_inks(props)
            self.lut = self.inks[0].lut
            self.coverages = [props.get_texture(name, DEFAULT_COVERAGE) for name in self.coverage_names]
            for name, texture in zip(self.coverage_names, self.coverages):
                check_coverage_texture(texture, name)
            self._stacks = {}
            self.primaries = self.model = self.premixed = self.looped = None
            self._update_primaries()
            delta = mi.BSDFFlags.DeltaReflection | mi.BSDFFlags.FrontSide
            smooth = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
            if self.paper.is_spatially_varying() or any(c.is_spatially_varying() for c in self.coverages):
                smooth = smooth | mi.BSDFFlags.SpatiallyVarying
                delta = delta | mi.BSDFFlags.SpatiallyVarying
            mi.BSDF.__init__(self, props)
            self.m_components = [delta, smooth]
            self.m_flags = delta | smooth

        # -------------------------------------------------------------- helpers
        def _update_primaries(self):
            """Decide which printed primaries can occur (from the coverages' data); with
            coverages that are numbers and Clapper–Yule, mix their tables into one
            (`inkbsdf.premix`). Stack tables come from the provider, once per stack; the
            per-primary lane model is built when first needed (`_lane_model`)."""
            supports = [coverage_support(t) for t in self.coverages]
            primaries = ((), (0,)) if len(self.inks) == 1 else possible_primaries(supports)
            if primaries != self.primaries:
                luts = []
                for subset in (s for s in primaries if s):
                    if len(subset) == 1:
                        luts.append((subset, self.inks[subset[0]].lut))
                        continue
                    if subset not in self._stacks:
                        self._stacks[subset] = stack_lut(tuple(self.inks[i] for i in stack_order(subset)))
                    luts.append((subset, self._stacks[subset]))
                if mi.is_polarized:        # every ink, even one with no area yet, and the stacks
                    for lut in [ink.lut for ink in self.inks] + [lut for _, lut in luts]:
                        check_polarizable(lut)
                self._luts, self.model, self.looped, self.primaries = luts, None, None, primaries
            self.premixed = None
            if self.coverage_model == "clapper-yule" and all(isinstance(c, float) for c in supports):
                model = premixed_model(supports, self._reduced())
                if model is not None:
                    self.premixed = PrintModel([((0,), model)], 1, self.coverage_model)
            if self.premixed is None:
                self._lane_model()      # its tables now, not while a kernel is being recorded

        def _reduced(self):
            """((subset, InkLUT), ...) of the primaries in this variant's colour space (each
            table reduced alone, as the unrolled model does, before any mixing or regridding)."""
            space = colour_space()
            return [(subset, reduce_lut(lut, space)) for subset, lut in self._luts]

        def _lane_model(self):
            """The lane model for this evaluation: the premixed table (coverages are numbers,
            Clapper–Yule), else in JIT variants the loop over each lane's non-zero primaries
            (`LoopedPrint`), else one lookup per primary (`PrintModel`: scalar variants, a
            single primary, or an input being differentiated, whose derivatives need the
            unrolled sums). Returns (model, coverages to use or None for the textures')."""
            tracked = self._inputs_tracked()
            if self.premixed is not None and not tracked:
                return self.premixed, [1.0]
            if self.looped is None and len(self._luts) > 1 and dr.is_jit_v(mi.Float):
                model = stacked_model([lut for _, lut in self._reduced()])
                self.looped = False if model is None else LoopedPrint(
                    [s for s, _ in self._luts], len(self.inks), self.coverage_model, model)
            if self.looped and not tracked:
                return self.looped, None
            if self.model is None:
                self.model = PrintModel([(s, model_for(lut)) for s, lut in self._luts], len(self.inks),
                                        self.coverage_model)
            return self.model, None

        def _inputs_tracked(self) -> bool:
            """True while a coverage or the paper albedo has derivatives enabled."""
            if not dr.is_diff_v(mi.Float):
                return False
            for texture in self.coverages + [self.paper]:
                params = mi.traverse(texture)
                if any(dr.grad_enabled(params[k]) for k in params.keys()):
                    return True
            return False

        def _incident(self, si, active):
            model, coverages = self._lane_model()
            if coverages is None:
                coverages = [_clamp01(t.eval_1(si, active)) for t in self.coverages]
            r = _clamp01(mi.UnpolarizedSpectrum(self.paper.eval(si, active)))
            return model.incident(si.wi, channel_coordinates(si), coverages, r)

        def _spec_prob(self, ctx, inc):
            """Probability that sample() picks the delta lobe, given the enabled lobes."""
            has_spec, has_diff = _lobes(ctx)
            if has_spec and has_diff:
                return inc.printer.spec_probability(inc)
            return 1.0 if has_spec else 0.0

        def _pdf(self, ctx, inc, wo):
            """Density of the smooth lobe's samples (the delta lobe has none)."""
            return (1.0 - self._spec_prob(ctx, inc)) * mi.warp.square_to_cosine_hemisphere_pdf(wo)

        def _mirror(self, ctx, si, inc, wo):
            """The delta lobe's weight × its selection probability (Σ a_S R_spec,S; a Mueller
            matrix in polarized variants) for the mirror direction `wo`."""
            if mi.is_polarized:
                b, c, s = inc.printer.mirror(inc)
                return in_stokes_frames(mirror_matrix(inc.specular, b, c, s), si.wi, wo, ctx.mode)
            return inc.specular

        def _with_mirror_derivative(self, ctx, si, inc, wo, value, pdf):
            """(value, pdf) of eval/eval_pdf, replaced at the mirror direction by the delta
            lobe's (Σ a_S R_spec,S, P_spec) while derivatives are tracked (docs/plugin.md,
            "Differentiable rendering"): `prb` and `direct_projective` differentiate a sampled
            direction's contribution through eval (`prb`: d value / value; `direct_projective`:
            d value / pdf), which sees only the smooth lobe; a direction within
            MIRROR_TOLERANCE of the mirror is, with probability ≈ 1 − 1e-6, a delta sample.
            Primal renders (no derivatives tracked) never take this branch."""
            if not (_lobes(ctx)[0] and dr.grad_enabled(inc.specular, inc.albedo_diffuse)):
                return value, pdf
            mirror_dir = mi.reflect(si.wi)
            at_mirror = inc.front & (dr.squared_norm(wo - mirror_dir) < MIRROR_TOLERANCE**2)
            value = dr.select(at_mirror, self._mirror(ctx, si, inc, mirror_dir), value)
            pdf = dr.select(at_mirror, dr.detach(self._spec_prob(ctx, inc)), pdf)
            return value, pdf

        # ------------------------------------------------------------ interface
        def sample(self, ctx, si, sample1, sample2, active=True):
            """Weights are value / detached pdf: the choice of lobe and the cosine-distributed
            direction do not move with the parameters, so a weight's derivative is the
            value's over the (fixed) probability of drawing it (docs/plugin.md,
            "Differentiable rendering")."""
            has_spec, has_diff = _lobes(ctx)
            bs = dr.zeros(mi.BSDFSample3f)
            if not (has_spec or has_diff):
                return bs, mi.Spectrum(0.0)
            inc = self._incident(si, active)
            p_spec = self._spec_prob(ctx, inc)
            pick_spec = (sample1 < p_spec) & inc.front
            wo_diff = mi.warp.square_to_cosine_hemisphere(sample2)
            wo_spec = mi.reflect(si.wi)
            bs.wo = dr.select(pick_spec, wo_spec, wo_diff)
            pdf_diff = (1.0 - p_spec) * mi.warp.square_to_cosine_hemisphere_pdf(wo_diff)
            bs.pdf = dr.select(pick_spec, p_spec, pdf_diff)
            bs.eta = 1.0
            bs.sampled_component = dr.select(pick_spec, mi.UInt32(SPECULAR), mi.UInt32(DIFFUSE))
            bs.sampled_type = dr.select(pick_spec, mi.UInt32(+mi.BSDFFlags.DeltaReflection),
                                        mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
            f_diff = inc.printer.diffuse(inc, si.wi, wo_diff)
            w_diff = safe_div(f_diff, dr.detach(pdf_diff))
            w_spec = self._mirror(ctx, si, inc, wo_spec) * safe_div(1.0, dr.detach(p_spec))
            if mi.is_polarized:
                w_diff = depolarizing(w_diff)
            weight = dr.select(pick_spec, w_spec, w_diff)
            ok = active & inc.front & (bs.pdf > 0)
            bs.pdf = dr.select(ok, bs.pdf, 0.0)
            return bs, dr.select(ok, weight, 0.0)

        def eval(self, ctx, si, wo, active=True):
            if not _lobes(ctx)[1]:
                return mi.Spectrum(0.0)
            inc = self._incident(si, active)
            value = _smooth(inc.printer.diffuse(inc, si.wi, wo))
            value, _ = self._with_mirror_derivative(ctx, si, inc, wo, value, 0.0)
            return dr.select(active, value, 0.0)

        def pdf(self, ctx, si, wo, active=True):
            if not _lobes(ctx)[1]:
                return mi.Float(0.0)
            inc = self._incident(si, active)
            ok = active & inc.front & (mi.Frame3f.cos_theta(wo) > 0)
            return dr.select(ok, self._pdf(ctx, inc, wo), 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            if not _lobes(ctx)[1]:
                return mi.Spectrum(0.0), mi.Float(0.0)
            inc = self._incident(si, active)
            ok = active & inc.front & (mi.Frame3f.cos_theta(wo) > 0)
            value = _smooth(inc.printer.diffuse(inc, si.wi, wo))
            value, pdf = self._with_mirror_derivative(ctx, si, inc, wo, value, self._pdf(ctx, inc, wo))
            return dr.select(ok, value, 0.0), dr.select(ok, pdf, 0.0)

        def traverse(self, callback):
            callback.put("paper", self.paper, mi.ParamFlags.Differentiable)
            for name, texture in zip(self.coverage_names, self.coverages):
                callback.put(name, texture, mi.ParamFlags.Differentiable)

        def parameters_changed(self, keys=()):
            if any(str(k).startswith("coverage") for k in keys) or not keys:
                self._update_primaries()

        def to_string(self):
            tables = ", ".join(repr(ink.lut.source) for ink in self.inks)
            stacks = ", ".join("/".join(str(i + 1) for i in stack_order(s)) for s in self.primaries
                               if len(s) > 1)
            return (f"InkBSDF[tables=[{tables}], coverage_model={self.coverage_model}, "
                    f"stacks=[{stacks}], paper={self.paper}, "
                    f"coverage=[{', '.join(str(c) for c in self.coverages)}]]")

    return InkBSDF


def bsdf_class():
    """The ink BSDF class for the active variant."""
    variant = check_variant(mi.variant())
    if variant not in _classes:
        _classes[variant] = _define_class()
    return _classes[variant]


def register() -> str:
    """Register the `ink` BSDF for the active Mitsuba variant; return the variant (VariantError
    when none is set). `follow_variant` (run by `import inkbsdf`) makes this automatic."""
    cls = bsdf_class()
    mi.register_bsdf(PLUGIN_NAME, plugin_factory(cls))    # bad input: a short error (inkbsdf/errors.py)
    return mi.variant()


def _on_variant_change(old, new) -> None:
    """Mitsuba's variant callback: register `ink` for the new variant. It never raises (an
    exception would break `mi.set_variant`): a failure is a warning, and `register()` repeats it."""
    if new is None:
        return
    try:
        register()
    except Exception as exc:            # noqa: BLE001 - reported, not raised into set_variant
        import warnings

        warnings.warn(f"inkbsdf: 'ink' not registered for variant '{new}': {exc}", stacklevel=2)


def follow_variant() -> None:
    """Register `ink` for the active variant (if any) and for every variant set from now on
    (Mitsuba's registry is per variant). Idempotent."""
    mi.detail.add_variant_callback(_on_variant_change)
    if mi.variant() is not None:
        register()
