"""What a table is computed from: the typed request, every default, and its content address.

Every entry point (the CLI, a scene's in-scene ink, the demo, the benchmarks, the figures)
makes its request with `table_request(...)`, which parses the ink and particle strings once into
typed objects and fills every default from this module — the same ink from any entry point is
the same table, with the same cache key.

    req = table_request("Y7.5+B7.5", "sphere:300")             # particle ink, default accuracy
    req = table_request("R30")                                 # molecular: the exact thin film
    req = table_request("Y15/B15")                             # Y15 printed over B15 (a stack)
    req.key()                                                  # content address in the cache

The key hashes everything that changes the numbers: the layers (molecular inks by their
base-pigment composition: a molecular G30 is Y15+B15), the grids, the wave settings of particle
inks, the polarisation, a fingerprint of the material data (`MaterialData.fingerprint`) and a
fingerprint of the code of the stages that produce the numbers (`fingerprint.code_fingerprint`).
Lengths in nm, angles in radians.
"""

from __future__ import annotations

import hashlib
import json
import warnings
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property

import numpy as np

from ..geometry.depolarisation import local_field_of
from ..geometry.spec import MOLECULAR_WORDS, ParticleSpec, parse_particles
from ..inks import Ink, parse_ink
from ..materials import MaterialData, default_materials
from .fingerprint import code_fingerprint
# the names and limits requests are checked against, re-exported: callers find them here
from .options import OPTION, WAVE_OPTIONS
from .request_checks import (MAX_ANGLES, TIERS, RequestError, ignored_on_molecular, parsed_option,  # noqa: F401
                             ThinLayerWarning, thin_layers_warning, fringe_aliasing_warning, validate)
from .schema import POLARISATIONS  # noqa: F401


# ---------------------------------------------------------------------------- the defaults
DEFAULT_THICKNESS_NM = 1000.0
DEFAULT_POLARISATION = "unpolarised"
#: the pigments' local field (docs/polarisation.md, "Local field") is on by default with
#: unpolarised light (the model closest to Maxwell's equations) and off with --polarisation te
#: (the paper's scalar model, today's tables exactly); --local-field / --no-local-field choose
LOCAL_FIELD_DEFAULT = {"unpolarised": True, "te": False}
#: "Y15/B15": Y15 printed over B15 (layers top first)
LAYER_SEPARATOR = "/"
#: molecular inks (exact thin film, cheap): 10-nm steps and 46 uniform incidence angles
FILM_WAVELENGTH_STEP_NM = 10.0
FILM_SIGMA_COUNT = 46
#: particle inks: 20-nm steps; solved incidence angles (90° is added as its analytic limit)
PARTICLE_WAVELENGTH_STEP_NM = 20.0
PARTICLE_SIGMA_DEG = (0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0)
WAVELENGTH_RANGE_NM = (380.0, 780.0)
DPHI_COUNT = 13


@dataclass(frozen=True)
class WaveSettings:
    """How a particle layer is sampled and solved (docs/tables.md)."""

    cell_nm: float = 2000.0                    # lateral period of the random cell
    grid: tuple[int, int, int] = (48, 48, 24)  # voxels (x, y, z)
    realizations: int = 6                      # random cells per wavelength
    azimuths: int = 1                          # incidence azimuths per realization (1: TE and TM
                                               # alternate over the realizations, wave_tier.alternates)
    solver_tol: float = 3e-3                   # wave solver relative residual (docs/wave_solver.md)
    tolerance: float = 0.01                    # tier choice: allowed error in Rbar, Tbar, diffuse
    seed: int = 1
    tier: str = "auto"
    target_se: float | None = None             # add realizations until max SE(Rbar, Tbar) ≤ this
    max_realizations: int = 64                 # … but never more than this
    wavelength_stride: int = 2                 # solve every k-th wavelength, film-guided between (spectral.py)


_DEFAULT_WAVE = WaveSettings()

#: accuracy presets of particle inks (wave settings and wavelength step); docs/tables.md has
#: each preset's measured colour error against `fine` and its cost
#: (wavelength_stride: the wave ensemble is solved on every k-th wavelength and film-guided in
#: between, spectral.py; `fine`, the reference, solves every wavelength)
ACCURACY = {
    "preview": (WaveSettings(grid=(40, 40, 20), realizations=2, azimuths=2, wavelength_stride=2),
                PARTICLE_WAVELENGTH_STEP_NM),
    "default": (WaveSettings(), PARTICLE_WAVELENGTH_STEP_NM),
    "fine": (WaveSettings(grid=(80, 80, 40), realizations=6, azimuths=2, solver_tol=1e-3, wavelength_stride=1), 10.0),
}


# ---------------------------------------------------------------------------- typed parts
@dataclass(frozen=True)
class Layer:
    """One printed layer: ink composition, its grains (None: molecular) and thickness."""

    ink: Ink
    particles: ParticleSpec | None
    thickness_nm: float = DEFAULT_THICKNESS_NM

    @property
    def molecular(self) -> bool:
        return self.particles is None

    @property
    def particles_label(self) -> str:
        return "molecular" if self.particles is None else self.particles.label

    def numeric_fields(self) -> dict:
        d = {"composition": [list(c) for c in self.ink.base_composition()],
             "thickness_nm": float(self.thickness_nm)}
        if not self.molecular:
            d["pigments"] = [[c, round(f, 12)] for c, f in self.ink.components]
            d["particles"] = self.particles.label
        return d


@dataclass(frozen=True)
class Grids:
    """The table's sampling: wavelengths (nm), incidence polar angles σ (rad, 0 … π/2, also the
    outgoing θ grid of R) and the number of Δφ nodes of R over [0, π]."""

    wavelengths_nm: tuple[float, ...]
    sigma_rad: tuple[float, ...]
    dphi_count: int = DPHI_COUNT

    @property
    def dphi_rad(self) -> np.ndarray:
        return np.linspace(0.0, np.pi, self.dphi_count)

    @property
    def solved_mask(self) -> np.ndarray:
        """Which σ nodes are solved: all but grazing 90°, whose value is its analytic limit."""
        return np.asarray(self.sigma_rad) < np.pi / 2 - 1e-9

    @property
    def solved_sigma_rad(self) -> np.ndarray:
        return np.asarray(self.sigma_rad)[self.solved_mask]


@dataclass(frozen=True)
class TableRequest:
    """Everything that determines a table's numbers.  Build with `table_request(...)`."""

    layers: tuple[Layer, ...]                   # top first; one for an ordinary ink
    grids: Grids
    wave: WaveSettings | None = None            # None when every layer is molecular
    polarisation: str = DEFAULT_POLARISATION
    materials: MaterialData = field(default_factory=default_materials)   # bulk constants
    accuracy: str = "default"                   # the preset the settings came from (a label)
    local_field: bool = LOCAL_FIELD_DEFAULT[DEFAULT_POLARISATION]   # pigments' local field (layer_materials)

    def layer_materials(self, index: int = 0) -> MaterialData:
        """The material data layer `index` is computed with: with the local field, its pigments
        enter with the local-field ε of its grains (`geometry.depolarisation`; dissolved
        pigment: the Lorentz sphere), else with their bulk ε."""
        if not self.local_field:
            return self.materials
        return self.materials.with_local_field(local_field_of(self.layers[index].particles))

    # ---- conveniences for the common single-layer case
    @property
    def molecular(self) -> bool:
        return all(layer.molecular for layer in self.layers)

    @property
    def solved_wavelength_indices(self) -> tuple[int, ...]:
        """The wavelengths (indices into grids.wavelengths_nm) the wave tiers solve: every
        --wavelength-stride-th and the last; the rest are film-guided (spectral.py)."""
        from .spectral import solved_indices

        stride = 1 if self.wave is None else self.wave.wavelength_stride
        return solved_indices(len(self.grids.wavelengths_nm), stride)

    @property
    def has_rough_top(self) -> bool:
        """Whether some particle layer's grains may stand out of the binder."""
        return any(layer.particles is not None and layer.particles.rough_top > 0 for layer in self.layers)

    @property
    def layer(self) -> Layer:
        if len(self.layers) != 1:
            raise RequestError(f"{self.ink_label} is a stack of {len(self.layers)} layers")
        return self.layers[0]

    @property
    def ink_label(self) -> str:
        return LAYER_SEPARATOR.join(layer.ink.label for layer in self.layers)

    @property
    def particles_label(self) -> str:
        labels = [layer.particles_label for layer in self.layers]
        return labels[0] if len(set(labels)) == 1 else LAYER_SEPARATOR.join(labels)

    @property
    def thickness_nm(self) -> float:
        """Total thickness of the layers, nm."""
        return float(sum(layer.thickness_nm for layer in self.layers))

    @property
    def kind(self) -> str:
        return "film" if self.molecular else "wave"

    def numeric_fields(self) -> dict:
        """The fields that change the numbers (the cache key's content)."""
        d = {"layers": [layer.numeric_fields() for layer in self.layers],
             "wavelengths_nm": list(self.grids.wavelengths_nm),
             "sigma_rad": list(self.grids.sigma_rad),
             "polarisation": self.polarisation,
             "local_field": self.local_field,
             "materials": self.materials.fingerprint,
             "code": code_fingerprint(self.kind)}
        if not self.molecular:
            d["dphi_count"] = self.grids.dphi_count
            d["wave"] = asdict(self.wave)
        return d

    def key(self) -> str:
        """The content address in the cache (computed once per request)."""
        return self._key

    @cached_property
    def _key(self) -> str:
        text = json.dumps(self.numeric_fields(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:24]

    def to_options(self) -> dict:
        """The request as `table_request` keywords (options.OPTIONS' names), every setting
        written out: table_request(**req.to_options()) == req."""
        layers = self.layers
        opts = {"ink": self.ink_label, "particles": self.particles_label,
                "thickness_nm": layers[0].thickness_nm if len(layers) == 1 else tuple(l.thickness_nm for l in layers),
                "wavelengths_nm": self.grids.wavelengths_nm, "sigma_rad": self.grids.sigma_rad,
                "dphi_count": self.grids.dphi_count, "polarisation": self.polarisation,
                "local_field": self.local_field, "accuracy": self.accuracy}
        if self.wave is not None:
            opts.update({name: getattr(self.wave, name) for name in WAVE_OPTIONS})
        return opts

    @classmethod
    def of_table(cls, table) -> "TableRequest":
        """The request of a table: `from_meta` for a table the builder wrote; a film made
        directly by the thin-film tier (tests, scripts) records its ink, thickness, polarisation
        and pigment field in its meta and its grids in its arrays, which is all a film's numbers
        depend on. RequestError for anything else."""
        meta = table.meta
        if isinstance(meta.get("settings"), dict) and "layers" in meta["settings"]:
            return cls.from_meta(meta)
        if meta.get("tier") != "thin-film" or meta.get("particles", "molecular") != "molecular":
            return cls.from_meta(meta)                      # raises, naming the table
        from .thinfilm_tier import LOCAL_FIELD_RULE

        thickness = meta.get("thickness_nm", DEFAULT_THICKNESS_NM)
        return table_request(meta["ink"], "molecular",
                             thickness_nm=tuple(thickness) if isinstance(thickness, list) else thickness,
                             wavelengths_nm=table.wavelengths, sigma_rad=table.sigma,
                             polarisation=meta.get("polarisation", "te"),
                             local_field=bool(meta.get("local_field", LOCAL_FIELD_RULE in meta.get("mixing_rule", ""))))

    @classmethod
    def from_meta(cls, meta: dict, materials: MaterialData | None = None) -> "TableRequest":
        """The request a table file was built from, read back from its meta (every option:
        `to_options` round-trips through table_meta). RequestError when the meta lacks the
        record (a table of another version) or the material data differ from `materials`
        (default: the package's)."""
        settings = meta.get("settings")
        if not isinstance(settings, dict) or "layers" not in settings:
            raise RequestError(f"table of {meta.get('ink', '?')}: its meta holds no request settings (a table "
                               "written by another version): build it again with `ink-tables build`")
        materials = materials or default_materials()
        if settings.get("materials") != materials.fingerprint:
            raise RequestError(f"table of {meta.get('ink', '?')}: computed with other material data "
                               f"(fingerprint {settings.get('materials')}, this package's {materials.fingerprint}): "
                               "build it again")
        opts = dict(meta.get("options") or {})
        if not opts:                    # tables written before `options` was recorded
            layers = settings["layers"]
            wave = settings.get("wave") or {}
            opts = {"ink": meta["ink"], "particles": meta.get("particles", "molecular"),
                    "thickness_nm": tuple(l["thickness_nm"] for l in layers) if len(layers) > 1
                    else layers[0]["thickness_nm"],
                    "wavelengths_nm": settings["wavelengths_nm"], "sigma_rad": settings["sigma_rad"],
                    "polarisation": settings["polarisation"], "local_field": settings["local_field"],
                    "accuracy": meta.get("accuracy", "default"), **{k: wave[k] for k in WAVE_OPTIONS if k in wave}}
            if "dphi_count" in settings:
                opts["dphi_count"] = settings["dphi_count"]
        opts = {k: tuple(v) if isinstance(v, list) else v for k, v in opts.items()}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")             # what the table's own build said already
            return table_request(opts.pop("ink"), opts.pop("particles"), materials=materials, **opts)

    def describe(self) -> str:
        """One line that tells requests apart: the ink, the grids, the sampling of a particle
        layer, and each other wave setting that differs from WaveSettings' default."""
        wl = self.grids.wavelengths_nm
        what = (f"{self.ink_label} {self.particles_label} H={'/'.join(f'{l.thickness_nm:g}' for l in self.layers)} nm"
                f", {self.polarisation}, {'local-field' if self.local_field else 'bulk'} pigment ε, "
                f"{len(wl)} λ {wl[0]:g}–{wl[-1]:g} nm × {len(self.grids.sigma_rad)} σ")
        if self.molecular:
            return what
        w = self.wave
        others = ("seed", "tier", "tolerance", "solver_tol", "target_se", "wavelength_stride") + (
            ("max_realizations",) if w.target_se is not None else ())   # the cap means nothing alone
        return (f"{what}, {w.realizations} realizations × {w.azimuths} azimuth{'s' if w.azimuths != 1 else ''}, grid "
                f"{'×'.join(map(str, w.grid))} over {w.cell_nm:g} nm"
                + "".join(f", {OPTION[k]} {getattr(w, k)}" for k in others
                          if getattr(w, k) != getattr(_DEFAULT_WAVE, k)))

    def with_wave(self, **changes) -> "TableRequest":
        """The same request with some wave settings changed (validated)."""
        req = replace(self, wave=replace(self.wave, **changes))
        validate(req)
        return req

    def with_grids(self, **changes) -> "TableRequest":
        req = replace(self, grids=replace(self.grids, **changes))
        validate(req)
        return req


def default_grids(accuracy: str, molecular: bool) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The default wavelengths (nm) and incidence angles (rad) of an ink's table: molecular inks
    every 10 nm and 46 uniform angles; particle inks the accuracy preset's step and the solved
    nodes (+ 90°)."""
    lo, hi = WAVELENGTH_RANGE_NM
    step = FILM_WAVELENGTH_STEP_NM if molecular else ACCURACY[accuracy][1]
    sigma = (np.linspace(0.0, np.pi / 2, FILM_SIGMA_COUNT) if molecular
             else np.radians(PARTICLE_SIGMA_DEG + (90.0,)))
    return (tuple(float(w) for w in np.arange(lo, hi + 0.5 * step, step)), tuple(float(s) for s in sigma))


def _count(n: int, noun: str) -> str:
    """'1 layer', '2 layers'."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _layers(ink, particles, thickness_nm) -> tuple[Layer, ...]:
    if isinstance(ink, (tuple, list)) and ink and all(isinstance(x, Layer) for x in ink):
        return tuple(ink)
    inks = [parsed_option("ink", ink, parse_ink, x) for x in (ink.split(LAYER_SEPARATOR) if isinstance(ink, str) else [ink])]
    if isinstance(particles, str):
        parts = particles.split(LAYER_SEPARATOR)
    else:
        parts = [particles]
    if len(parts) == 1:
        parts = parts * len(inks)
    if len(parts) != len(inks):
        raise RequestError(f"--particles {particles!r} names {len(parts)} layers, the ink {ink!r} has {len(inks)}")
    specs = [None if p is None or (isinstance(p, str) and p.strip().lower() in MOLECULAR_WORDS)
             else p if isinstance(p, ParticleSpec) else parsed_option("particles", particles, parse_particles, p)
             for p in parts]
    thick = thickness_nm if isinstance(thickness_nm, (tuple, list)) else [thickness_nm] * len(inks)
    if len(thick) != len(inks):
        fix = ("give one value (nm)" if len(inks) == 1
               else f"give one value for all layers or {len(inks)}, one per layer (top first)")
        raise RequestError(f"--thickness gives {_count(len(thick), 'value')} for {_count(len(inks), 'layer')}: {fix}")
    layers = []
    for ink_, spec, h in zip(inks, specs, thick):
        h = DEFAULT_THICKNESS_NM if h is None else h
        try:
            h = float(h)
        except (TypeError, ValueError):
            raise RequestError(f"--thickness {h!r} is not a number of nm") from None
        layers.append(Layer(ink_, spec, h))
    return tuple(layers)


def table_request(ink, particles="molecular", *, thickness_nm=None, accuracy: str = "default",
                  wavelengths_nm=None, sigma_rad=None, dphi_count: int = DPHI_COUNT,
                  polarisation: str = DEFAULT_POLARISATION, materials: MaterialData | None = None,
                  local_field: bool | None = None, **wave_overrides) -> TableRequest:
    """The request for an ink, with every default filled from this module and validated.

    ink: a spec ('R30', 'Y7.5+B7.5', 'G30', 'clear', 'Y15/B15' for Y15 printed over B15) or Ink;
    particles: 'molecular' or a particle spec (one for all layers, or 'a/b' per layer);
    thickness_nm: per layer (a number, or one per layer); accuracy: a key of ACCURACY;
    wavelengths_nm / sigma_rad: explicit grids (else the defaults for the kind of ink);
    local_field: the pigments' local-field ε (None: LOCAL_FIELD_DEFAULT of the polarisation);
    wave_overrides: fields of WaveSettings (cell_nm, grid, realizations, azimuths, solver_tol,
    tolerance, seed, tier).
    """
    if accuracy not in ACCURACY:
        raise RequestError(f"--accuracy {accuracy!r}: choose one of {', '.join(ACCURACY)}")
    unknown = set(wave_overrides) - set(WaveSettings.__dataclass_fields__)
    if unknown:
        raise RequestError(f"unknown table option(s) {', '.join(sorted(unknown))}: expected some of "
                           + ", ".join(WaveSettings.__dataclass_fields__))
    layers = _layers(ink, particles, thickness_nm)
    molecular = all(layer.molecular for layer in layers)
    preset = ACCURACY[accuracy][0]
    default_wavelengths = wavelengths_nm is None
    if wavelengths_nm is None or sigma_rad is None:
        default_wl, default_sigma = default_grids(accuracy, molecular)
        wavelengths_nm = default_wl if wavelengths_nm is None else wavelengths_nm
        sigma_rad = default_sigma if sigma_rad is None else sigma_rad
    grids = Grids(tuple(float(w) for w in np.atleast_1d(wavelengths_nm)),
                  tuple(float(s) for s in np.atleast_1d(sigma_rad)), int(dphi_count))
    tier = wave_overrides.get("tier", "auto")
    if molecular and tier not in ("auto", "thin-film"):
        raise RequestError(f"--tier {tier}: a molecular ink is an exact thin film; give --particles "
                           "to use the wave tiers")
    wave = None
    if not molecular:
        fields = dict(asdict(preset), **wave_overrides)
        fields["grid"] = tuple(fields["grid"])
        if len(layers) > 1 and "grid" not in wave_overrides:
            # the preset's z cells are for one 1000-nm layer: a stack keeps their height
            nx, ny, nz = fields["grid"]
            fields["grid"] = (nx, ny, sum(max(1, round(nz * layer.thickness_nm / DEFAULT_THICKNESS_NM))
                                          for layer in layers))
        if fields["target_se"] is None and "max_realizations" in wave_overrides:
            # the cap of --target-se changes nothing without it: one table
            warnings.warn(f"{OPTION.get('max_realizations')} is the cap of {OPTION.get('target_se')}: "
                          "ignored without it", stacklevel=2)
        if fields["target_se"] is None or "max_realizations" not in wave_overrides:
            # a cap not given follows --realizations (the preset's, unless that asks for more)
            fields["max_realizations"] = max(preset.max_realizations, fields["realizations"]) \
                if isinstance(fields["realizations"], (int, np.integer)) else preset.max_realizations
        wave = WaveSettings(**fields)
    else:                   # the preset and settings of the wave solver mean nothing for a homogeneous layer
        ignored = (["accuracy"] if accuracy != "default" else []) + sorted(set(wave_overrides) - {"tier"})
        if ignored:
            warnings.warn(ignored_on_molecular(LAYER_SEPARATOR.join(l.ink.label for l in layers),
                                               [OPTION.get(k, k) for k in ignored]), stacklevel=2)
    materials = materials or default_materials()
    if local_field is None:
        local_field = LOCAL_FIELD_DEFAULT.get(polarisation, True)   # an unknown one is refused below
    if isinstance(local_field, (bool, np.bool_)) and not any(layer.ink.components for layer in layers):
        local_field = False                       # no pigment to correct: one table for clear varnish
    req = TableRequest(layers, grids, wave, polarisation, materials, accuracy, local_field)
    validate(req)
    thin = thin_layers_warning([layer.thickness_nm for layer in layers])
    if thin:                                      # valid, but most likely µm typed as nm
        warnings.warn(thin, ThinLayerWarning, stacklevel=2)
    # valid, but the default sampling may miss a film's fringes (an explicit grid is the caller's
    # choice; particle inks' steps are their accuracy preset's, measured against fine)
    aliased = (fringe_aliasing_warning(req.thickness_nm, grids.wavelengths_nm, req.materials.binder_index)
               if default_wavelengths and molecular else None)
    if aliased:
        warnings.warn(aliased, stacklevel=2)
    return req
