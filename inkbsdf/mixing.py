"""A print of one to four inks on paper, per lane in Dr.Jit: Demichel weights over the printed
primaries and the Clapper–Yule or Murray–Davies coverage model (docs/plugin.md, "The model").

With coverages c_i (printing order), paper albedo r, and for each printed primary S (a set of
inks; S = ∅ bare paper, T̄ = τ̄ = 1, ρ̄ = R = R_spec = 0) its table's quantities (`model`):

    a_S = Π_{i∈S} c_i Π_{j∉S} (1 − c_j)
    Clapper–Yule:  f = Σ a_S [R_S/π + R_spec,S δ] + r [Σ a_S T̄_S(σ)] [Σ a_S T̄_S(θ)] / (π (1 − r Σ a_S ρ̄_S))
    Murray–Davies: f = Σ a_S [R_S/π + R_spec,S δ + r T̄_S(σ) T̄_S(θ) / (π (1 − r ρ̄_S))]

`PrintModel.incident` computes what depends on ωi only (one σ lookup per primary; equal grids
are located once); `diffuse` adds what depends on ωo. In polarized variants `mirror` gives the
delta lobe's Mueller elements Σ a_S (b, C, S)_S besides its M00 = `Incident.specular`. The
reference (NumPy) implementation of the same formulas is `solver.printing`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import drjit as dr
import mitsuba as mi

from solver.printing import check_coverage_model

from .model import InkModel, cos_dphi, lane_mean, safe_div


@dataclass(frozen=True)
class Layer:
    """One printed primary (an ink or a stack of inks) at this lane."""

    model: InkModel
    weight: object      # Float a_S
    lam: tuple          # located wavelengths per Spectrum channel ((i, t), ...)
    sig: tuple          # located σ (i, t)
    coupling: object    # Murray–Davies: a_S·r·T̄_S(σ)/(π(1 − r ρ̄_S)), multiplies T̄_S(θ); else None


@dataclass(frozen=True)
class Incident:
    """Per-lane quantities fixed by ωi, the wavelengths, the coverages and the paper albedo."""

    front: object           # Bool: ωi above the surface
    layers: tuple           # Layer per evaluated primary S ≠ ∅
    bare: object            # Float a_∅
    coupling: object        # Clapper–Yule: r·Σ a_S T̄_S(σ)/(π(1 − r Σ a_S ρ̄_S)), multiplies Σ a_S T̄_S(θ)
    paper: object           # Murray–Davies: a_∅·r/π
    specular: object        # UnpolarizedSpectrum: Σ a_S R_spec,S(σ), weight of the delta lobe
    albedo_diffuse: object  # UnpolarizedSpectrum: ∫ (smooth part of f) cos θo dωo
    printer: object = None  # the PrintModel that made it (its `diffuse`, `mirror` go with it)
    lanes: object = None    # LoopedPrint: (nonzero-primary bits, coverages, λ, σ located, paper)


def demichel(coverages, subset):
    """a_S for the lane's coverages (list of Float, clamped)."""
    w = None
    for i, c in enumerate(coverages):
        term = c if i in subset else 1.0 - c
        w = term if w is None else w * term
    return w


class Located:
    """Coordinates located once per grid during one evaluation (grids shared by several tables)."""

    def __init__(self, values):
        self.values, self._memo = values, {}

    def on(self, axis):
        hit = self._memo.get(axis.key)
        if hit is None:
            hit = self._memo[axis.key] = (tuple(axis.locate(v) for v in self.values)
                                          if isinstance(self.values, tuple) else axis.locate(self.values))
        return hit


class PrintModel:
    """The inks of one BSDF: `primaries` = ((subset, InkModel), ...) for the printed primaries
    S ≠ ∅ that can occur (subsets of ascending 0-based ink indices), `n_inks` coverages."""

    def __init__(self, primaries, n_inks: int, coverage_model: str):
        self.primaries = tuple(primaries)
        self.n_inks = int(n_inks)
        self.clapper_yule = check_coverage_model(coverage_model) == "clapper-yule"
        self.has_diffuse = any(m.has_diffuse for _, m in self.primaries)

    def incident(self, wi, wavelengths, coverages, paper) -> Incident:
        """Everything that depends on ωi only; `coverages` a list of Float in [0, 1] (printing
        order), `paper` an UnpolarizedSpectrum in [0, 1]."""
        r = paper
        cos_i = mi.Frame3f.cos_theta(wi)
        n = dr.size_v(mi.UnpolarizedSpectrum)
        lam = Located(tuple(wavelengths[j] for j in range(n)))
        sig = Located(dr.safe_acos(cos_i))
        bare = demichel(coverages, ())
        layers, terms = [], []
        for subset, model in self.primaries:
            a = demichel(coverages, subset)
            loc_l, loc_s = lam.on(model.lam_axis), sig.on(model.sig_axis)
            q = model.at_incidence(loc_l, loc_s)
            coupling = through = None
            if not self.clapper_yule:
                # r·T̄(σ)/(1 − r·ρ̄): the paper's bounces under this primary (ρ̄ < 1 unless
                # lossless and totally reflecting, which no table has; guarded anyway).
                through = safe_div(r * q.t_in, 1.0 - r * q.rho)
                coupling = a * through * dr.inv_pi
            layers.append(Layer(model, a, loc_l, loc_s, coupling))
            terms.append((a, q, through))
        if self.clapper_yule:
            inc = self._clapper_yule(cos_i, tuple(layers), bare, terms, r)
        else:
            inc = self._murray_davies(cos_i, tuple(layers), bare, terms, r)
        return replace(inc, printer=self)

    @staticmethod
    def _clapper_yule(cos_i, layers, bare, terms, r) -> Incident:
        t_in, rho, tau, specular, layer_albedo = bare, 0.0, bare, 0.0, 0.0
        for a, q, _ in terms:
            t_in = t_in + a * q.t_in
            rho = rho + a * q.rho
            tau = tau + a * q.tau
            specular = specular + a * q.r_spec
            if q.r_diff is not None:
                layer_albedo = layer_albedo + a * q.r_diff
        # The paper's bounces under the mixed upper surface: r·Σ a T̄(σ)/(1 − r·Σ a ρ̄).
        through = safe_div(r * t_in, 1.0 - r * rho)
        return Incident(front=cos_i > 0, layers=layers, bare=bare, coupling=through * dr.inv_pi,
                        paper=None, specular=mi.UnpolarizedSpectrum(specular),
                        albedo_diffuse=layer_albedo + through * tau)

    @staticmethod
    def _murray_davies(cos_i, layers, bare, terms, r) -> Incident:
        albedo, specular = bare * r, 0.0
        for a, q, through in terms:
            albedo = albedo + a * (through * q.tau)
            if q.r_diff is not None:
                albedo = albedo + a * q.r_diff
            specular = specular + a * q.r_spec
        return Incident(front=cos_i > 0, layers=layers, bare=bare, coupling=None,
                        paper=bare * r * dr.inv_pi, specular=mi.UnpolarizedSpectrum(specular),
                        albedo_diffuse=albedo)

    def spec_probability(self, inc: Incident):
        """Probability of sampling the delta lobe: mean_λ(specular) / mean_λ(total albedo)."""
        spec = lane_mean(inc.specular)
        return safe_div(spec, spec + lane_mean(inc.albedo_diffuse))

    def mirror(self, inc: Incident):
        """Σ a_S (b, C, S)_S: the delta lobe's Mueller elements besides M00 = inc.specular, in
        the frame of the plane of incidence (`inkbsdf.lut.mirror_mueller`). Each primary's
        matrix is weighted by its Demichel weight (Murray–Davies and Clapper–Yule alike: the
        mirror beams never reach the paper)."""
        b = c = s = 0.0
        for layer in inc.layers:
            lb, lc, ls = layer.model.mirror(layer.lam, layer.sig)
            b, c, s = b + layer.weight * lb, c + layer.weight * lc, s + layer.weight * ls
        return tuple(mi.UnpolarizedSpectrum(x) for x in (b, c, s))

    def diffuse(self, inc: Incident, wi, wo):
        """Smooth part of f(ωi, ωo)·cos θo (UnpolarizedSpectrum); zero unless both directions
        are above."""
        cos_o = mi.Frame3f.cos_theta(wo)
        theta = Located(dr.safe_acos(cos_o))
        if self.clapper_yule:
            t_out = inc.bare
            for layer in inc.layers:
                t_out = t_out + layer.weight * layer.model.exit_transmittance(
                    layer.lam, theta.on(layer.model.sig_axis))
            f = inc.coupling * t_out
        else:
            f = inc.paper
            for layer in inc.layers:
                f = layer.coupling * layer.model.exit_transmittance(
                    layer.lam, theta.on(layer.model.sig_axis)) + f
        if self.has_diffuse:
            dphi = Located(dr.safe_acos(cos_dphi(wi, wo)))
            for layer in inc.layers:
                m = layer.model
                if m.has_diffuse:
                    R = m.layer(layer.lam, layer.sig, theta.on(m.theta_axis), dphi.on(m.dphi_axis))
                    f += layer.weight * dr.inv_pi * R
        valid = inc.front & (cos_o > 0)
        return dr.select(valid, f * cos_o, 0.0)


class LoopedPrint:
    """The same print as `PrintModel`, for JIT variants: per lane only the printed primaries
    with a Demichel weight > 0, visited in one Dr.Jit loop over the set bits of a per-lane mask,
    their tables stacked in one buffer per quantity (`InkModel.stacked`, on the union of their
    grids: `inkbsdf.premix.common_grid`). One copy of the lookups in the kernel whatever the
    number of primaries, and a lane pays for the primaries it shows: one on a halftone (each
    texel inked or not), all of them where every coverage is strictly between 0 and 1.
    Reverse mode through a symbolic loop needs a `max_iterations` hint in Dr.Jit 1.5: the plugin
    uses this class only while no input of the BSDF is being differentiated."""

    def __init__(self, subsets, n_inks: int, coverage_model: str, model: InkModel):
        """`subsets`: the printed primaries S ≠ ∅ in the order of `model`'s stacked tables."""
        self.subsets = tuple(tuple(s) for s in subsets)
        self.n_inks = int(n_inks)
        self.clapper_yule = check_coverage_model(coverage_model) == "clapper-yule"
        self.model = model
        self.has_diffuse = self.model.has_diffuse
        self._subset_bits = mi.UInt32([sum(1 << i for i in s) for s in self.subsets])

    def _weight(self, coverages, bits):
        """a_S of the subset whose ink bits are `bits` (per lane)."""
        w = None
        for i, c in enumerate(coverages):
            term = dr.select(((bits >> i) & 1) != 0, c, 1.0 - c)
            w = term if w is None else w * term
        return w

    def _nonzero(self, coverages):
        """Per-lane bit mask of the primaries (slots) with a_S > 0."""
        mask = mi.UInt32(0)
        for slot, subset in enumerate(self.subsets):
            mask = mask | dr.select(demichel(coverages, subset) > 0, mi.UInt32(1 << slot), mi.UInt32(0))
        return mask

    def _visit(self, coverages, mask, step, totals):
        """totals after step(slot, a_S, totals) for every set bit of `mask` (a Dr.Jit loop)."""
        def body(mask, *totals):
            slot = dr.tzcnt(mask)
            a = self._weight(coverages, dr.gather(mi.UInt32, self._subset_bits, slot))
            new = step(slot, a, totals)
            return (mask & (mask - 1),) + tuple(type(t)(x) for t, x in zip(totals, new))
        out = dr.while_loop(state=(mask,) + tuple(totals), cond=lambda mask, *_: mask != 0, body=body,
                            labels=("mask",) + tuple(f"total{k}" for k in range(len(totals))))
        return out[1:]

    def incident(self, wi, wavelengths, coverages, paper) -> Incident:
        r = paper
        cos_i = mi.Frame3f.cos_theta(wi)
        n = dr.size_v(mi.UnpolarizedSpectrum)
        m = self.model
        lam = tuple(m.lam_axis.locate(wavelengths[j]) for j in range(n))
        sig = m.sig_axis.locate(dr.safe_acos(cos_i))
        coverages = [mi.Float(c) for c in coverages]
        bare = demichel(coverages, ())
        mask = self._nonzero(coverages)
        zero = mi.UnpolarizedSpectrum(0.0)
        lanes = (mask, coverages, lam, sig, r)
        if self.clapper_yule:
            def step(slot, a, totals):
                t_in, rho, tau, spec, diff = totals
                q = m.at_incidence(lam, sig, block=slot)
                return (t_in + a * q.t_in, rho + a * q.rho, tau + a * q.tau, spec + a * q.r_spec,
                        diff + a * q.r_diff if q.r_diff is not None else diff)
            t_in, rho, tau, spec, diff = self._visit(coverages, mask, step, (zero, zero, zero, zero, zero))
            t_in, tau = t_in + bare, tau + bare
            through = safe_div(r * t_in, 1.0 - r * rho)
            return Incident(front=cos_i > 0, layers=(), bare=bare, coupling=through * dr.inv_pi, paper=None,
                            specular=mi.UnpolarizedSpectrum(spec), albedo_diffuse=diff + through * tau,
                            printer=self, lanes=lanes)

        def step(slot, a, totals):
            albedo, spec = totals
            q = m.at_incidence(lam, sig, block=slot)
            albedo = albedo + a * (safe_div(r * q.t_in, 1.0 - r * q.rho) * q.tau)
            if q.r_diff is not None:
                albedo = albedo + a * q.r_diff
            return albedo, spec + a * q.r_spec
        albedo, spec = self._visit(coverages, mask, step, (zero, zero))
        return Incident(front=cos_i > 0, layers=(), bare=bare, coupling=None, paper=bare * r * dr.inv_pi,
                        specular=mi.UnpolarizedSpectrum(spec), albedo_diffuse=albedo + bare * r,
                        printer=self, lanes=lanes)

    def spec_probability(self, inc: Incident):
        spec = lane_mean(inc.specular)
        return safe_div(spec, spec + lane_mean(inc.albedo_diffuse))

    def mirror(self, inc: Incident):
        mask, coverages, lam, sig, _ = inc.lanes
        zero = mi.UnpolarizedSpectrum(0.0)

        def step(slot, a, totals):
            lb, lc, ls = self.model.mirror(lam, sig, block=slot)
            return tuple(t + a * x for t, x in zip(totals, (lb, lc, ls)))
        return tuple(mi.UnpolarizedSpectrum(x) for x in self._visit(coverages, mask, step, (zero, zero, zero)))

    def diffuse(self, inc: Incident, wi, wo):
        mask, coverages, lam, sig, r = inc.lanes
        m = self.model
        cos_o = mi.Frame3f.cos_theta(wo)
        theta = dr.safe_acos(cos_o)
        theta_sig = m.sig_axis.locate(theta)
        if self.has_diffuse:
            theta_r = m.theta_axis.locate(theta)
            dphi = m.dphi_axis.locate(dr.safe_acos(cos_dphi(wi, wo)))
        clapper_yule = self.clapper_yule

        def step(slot, a, totals):
            light, layer = totals
            t_out = m.exit_transmittance(lam, theta_sig, block=slot)
            if clapper_yule:
                light = light + a * t_out
            else:
                q = m.at_incidence(lam, sig, block=slot)
                light = light + a * safe_div(r * q.t_in, 1.0 - r * q.rho) * dr.inv_pi * t_out
            if self.has_diffuse:
                layer = layer + a * dr.inv_pi * m.layer(lam, sig, theta_r, dphi, block=slot)
            return light, layer
        zero = mi.UnpolarizedSpectrum(0.0)
        light, layer = self._visit(coverages, mask, step, (zero, zero))
        f = inc.coupling * (inc.bare + light) if clapper_yule else inc.paper + light
        f = f + layer
        valid = inc.front & (cos_o > 0)
        return dr.select(valid, f * cos_o, 0.0)
