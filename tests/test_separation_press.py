"""Separation like a press (solver.apps.separation): the print model under the 45:0 D50
measurement, perceptual gamut mapping (smooth ramps stay monotone in L*, no notch), black
generation with a total area coverage limit, the 3-D separation table, the CGATS
characterisation chart (read back by the test's own CGATS reader)."""

import numpy as np
import pytest

from solver.apps.separation import (BlackGeneration, GamutBoundary, GamutSettings, PrintColourModel, SeparationLUT,
                                   Separator, delta_e2000, map_to_gamut, printed_inks, separate_lab, srgb8_to_lab)
from solver.apps.separation.black import BlackGenerationError, InkingObjective, black_index, find_black
from solver.colour.measurement import DEFAULT, parse_measurement

RYB = ("R30", "Y30", "B30")
RYBK = ("R30", "Y30", "B30", "R15+Y15+B15")       # a composite black stands in for K in the tests


@pytest.fixture(scope="module")
def ryb():
    return PrintColourModel.build(printed_inks(RYB), 0.9, "clapper-yule")


@pytest.fixture(scope="module")
def rybk():
    return PrintColourModel.build(printed_inks(RYBK), 0.9, "clapper-yule")


@pytest.fixture(scope="module")
def ryb_boundary(ryb):
    return GamutBoundary.build(ryb, 3.0)


@pytest.fixture(scope="module")
def process_separator():
    """The package's process inks (K, C, M, Y) on their paper, the print command's defaults."""
    from solver.apps.separation import PrintSettings
    from solver.apps.separation.job import build_separator
    from solver.apps.separation.printset import parse_ink_list

    settings = PrintSettings(inks=parse_ink_list("process"))
    return build_separator(settings, printed_inks(settings.inks))


@pytest.fixture(scope="module")
def ryb_separator(ryb):
    return Separator.build(ryb)


@pytest.fixture(scope="module")
def rybk_separator(rybk):
    return Separator.build(rybk, black=black_index(rybk, RYBK, None))


# ------------------------------------------------------------------ the print model at 45:0
@pytest.mark.parametrize("coverage_model", ["clapper-yule", "murray-davies"])
def test_solids_are_the_measurement_of_their_tables(coverage_model):
    """A solid (one primary at full area) is that primary's table measured at 45:0 D50 by
    solver.colour.measurement (its own code: reflectance factor of one table on paper)."""
    printed = printed_inks(RYB)
    model = PrintColourModel.build(printed, 0.9, coverage_model, intent="absolute")
    for i, table in enumerate(printed.inks):
        np.testing.assert_allclose(model.lab(np.eye(3)[i]), DEFAULT.lab(table, 0.9), atol=1e-9)
    np.testing.assert_allclose(model.lab(np.ones(3)), DEFAULT.lab(printed.stacks[(0, 1, 2)], 0.9), atol=1e-9)
    assert model.measurement.label == "45:0/D50/2°"


def test_45_0_excludes_the_gloss_that_d0_sees():
    """The mirror term is a grey floor under d:0: the same dark overprint is darker at 45:0."""
    printed = printed_inks(RYB)
    dark_45 = PrintColourModel.build(printed, 0.9, intent="absolute").lab(np.ones(3))[0]
    dark_d0 = PrintColourModel.build(printed, 0.9, intent="absolute",
                                     measurement=parse_measurement("d:0", "D50")).lab(np.ones(3))[0]
    assert dark_45 < dark_d0 - 10.0


# ------------------------------------------------------------------ gamut mapping
def _ramp(a, b, n=64):
    t = np.linspace(0.0, 1.0, n)[:, None]
    return np.round(np.asarray(a, float) * (1 - t) + np.asarray(b, float) * t)


RAMPS = {"blue→white": ((0, 0, 255), (255, 255, 255)), "black→dark blue": ((0, 0, 0), (0, 0, 128)),
         "black→grey": ((0, 0, 0), (96, 96, 96)), "green→black": ((0, 255, 0), (0, 0, 0)),
         "red→white": ((255, 0, 0), (255, 255, 255))}
L_TOLERANCE = 0.02          # L* (a fiftieth of a just-noticeable difference)


def _step_spike(printed_lab, source_lab) -> float:
    """Largest ratio of a printed step (ΔE2000 between neighbours) to the median over its ±4
    neighbours, each step relative to the source's own step: a notch is one step far larger than
    its neighbours; a smooth compression changes the steps slowly."""
    st = delta_e2000(printed_lab[1:], printed_lab[:-1]) / np.maximum(delta_e2000(source_lab[1:], source_lab[:-1]), 1e-9)
    local = np.array([np.median(st[max(0, i - 4):i + 5]) for i in range(st.size)])
    return float(np.max(st / np.maximum(local, 1e-12)))


@pytest.mark.parametrize("name", list(RAMPS))
@pytest.mark.parametrize("inks", ["ryb", "rybk", "process"])
def test_ramps_stay_monotone_and_smooth(name, inks, ryb_separator, rybk_separator, process_separator):
    """A smooth ramp (monotone in L*) is monotone in L* after gamut mapping and separation, the
    print matches the mapped colours, and no step spikes against its neighbours (a notch from
    nearest-colour clipping does: the clip test below)."""
    sep_ = {"ryb": ryb_separator, "rybk": rybk_separator, "process": process_separator}[inks]
    source = srgb8_to_lab(_ramp(*RAMPS[name]))
    assert np.all(np.diff(source[:, 0]) > 0) or np.all(np.diff(source[:, 0]) < 0)
    sep, _ = sep_.separate_srgb(_ramp(*RAMPS[name]) / 255.0)
    L = sep.printed_lab[:, 0]
    sign = np.sign(source[-1, 0] - source[0, 0])
    assert np.min(sign * np.diff(L)) > -L_TOLERANCE, (name, np.diff(L).min())
    assert sep.delta_e76.max() < 3.0, name                      # concave corners of the gamut: closest colour
    assert _step_spike(sep.printed_lab, source) < 3.0, name


def test_colorchecker_printed_with_the_process_inks(process_separator):
    """The 24 ColorChecker patches (colour-science's ColorChecker 2005 reference, D50) printed
    from their 8-bit sRGB values with the process inks: ΔE2000 mean ≤ 3, max ≤ 8 (issue 21)."""
    import colour

    cc = colour.CCS_COLOURCHECKERS["ColorChecker 2005"]
    xyz = colour.xyY_to_XYZ(np.array(list(cc.data.values())))
    reference = colour.XYZ_to_Lab(xyz, cc.illuminant)
    rgb = colour.XYZ_to_sRGB(xyz, illuminant=cc.illuminant, chromatic_adaptation_transform="Bradford")
    sep, _ = process_separator.separate_srgb(np.round(np.clip(rgb, 0, 1) * 255) / 255)
    de = delta_e2000(sep.printed_lab, reference)
    assert de.mean() <= 3.0 and de.max() <= 8.0, (de.mean(), de.max())
    k = sep.coverages[:, process_separator.objective.black]
    assert k[18] < k[21] < k[23]                  # the grey row: white, neutral 5, black: more black


def test_clipping_makes_the_notch_that_mapping_avoids(ryb, ryb_separator):
    """The blue→white ramp clipped to the closest printable colour (the old separation) has a
    spike in its steps; the perceptual mapping has none."""
    source = srgb8_to_lab(_ramp(*RAMPS["blue→white"]))
    clipped = separate_lab(ryb, source)
    mapped, _ = ryb_separator.separate_srgb(_ramp(*RAMPS["blue→white"]) / 255.0)
    assert _step_spike(clipped.printed_lab, source) > 2 * _step_spike(mapped.printed_lab, source)


def test_mapping_keeps_hue_and_lands_inside(ryb_boundary):
    """The perceived (Oklab) hue is unchanged (away from the neutral axis); every mapped colour
    lies in the print's gamut; neutrals map by black-point compensation alone."""
    from solver.colour.hue import oklab_hue

    rng = np.random.default_rng(4)
    src = srgb8_to_lab(rng.integers(0, 256, (3000, 3)))
    out = map_to_gamut(src, ryb_boundary)
    assert ryb_boundary.contains(out).all()
    chroma = np.hypot(src[:, 1], src[:, 2])
    keep = (chroma > 5) & (np.hypot(out[:, 1], out[:, 2]) > 1) & (out[:, 0] > 5)
    dh = (oklab_hue(out[keep]) - oklab_hue(src[keep]) + 180) % 360 - 180
    assert np.abs(dh).max() < 1e-3
    grey = srgb8_to_lab(np.repeat(np.arange(0, 256, 15)[:, None], 3, 1))
    np.testing.assert_allclose(map_to_gamut(grey, ryb_boundary)[:, 0], ryb_boundary.lightness_map(grey[:, 0]), atol=2e-3)


def test_saturated_blues_keep_their_perceived_hue(process_separator):
    """A saturated sRGB blue sky compressed into the process gamut keeps the hue it is seen as:
    against an independent hue-linear space (IPT, Ebner & Fairchild 1998, from colour-science)
    the mapped colours' hue moves ≤ 3°, where keeping CIELAB's hue at the same L*, C* would move
    it 6–27° toward violet (the proof's lavender sky)."""
    import colour

    from solver.colour.cie import lab_to_xyz, white_xyz

    sep = process_separator
    src = srgb8_to_lab(np.array([[26, 90, 242], [40, 110, 250], [0, 60, 200], [60, 140, 255], [0, 0, 255]]))
    out = map_to_gamut(src, sep.boundary, sep.gamut, sep.model.measurement)
    white = white_xyz("D50", "2")
    d65 = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"])

    def ipt_hue(lab):
        xyz = colour.chromatic_adaptation(lab_to_xyz(lab, white) / white[1], white / white[1], d65,
                                          method="Von Kries", transform="Bradford")
        ipt = colour.XYZ_to_IPT(xyz)
        return np.degrees(np.arctan2(ipt[..., 2], ipt[..., 1]))

    h_lab = np.arctan2(src[:, 2], src[:, 1])
    chroma = np.hypot(out[:, 1], out[:, 2])
    cielab_kept = np.stack([out[:, 0], chroma * np.cos(h_lab), chroma * np.sin(h_lab)], -1)
    shift = lambda lab: np.abs((ipt_hue(lab) - ipt_hue(src) + 180) % 360 - 180)      # noqa: E731
    assert np.all(chroma < 0.7 * np.hypot(src[:, 1], src[:, 2]))       # really compressed
    assert shift(out).max() <= 3.0, shift(out)
    assert shift(cielab_kept).min() >= 6.0, shift(cielab_kept)


def _outside_true_gamut(model, tac, lab, window_l=3.0):
    """How far (CIELAB units, within the colour's hue slice) each colour lies outside the
    print's true gamut: the distance in (C*, L*) to the region C* ≤ C_true(L*) of the brute-force
    oracle (tests/oracles.py, over the coverage polytope's faces) within ±`window_l` of L*."""
    from oracles import gamut_chroma_max
    from solver.apps.separation.gamut import to_lch
    from solver.colour.hue import oklab_hue

    L, C, h = to_lch(lab)
    oracle = lambda L_, h_: gamut_chroma_max(model.lab, oklab_hue, model.n_inks, tac, L_, h_, nodes=49)  # noqa: E731
    out = np.maximum(C - oracle(L, h), 0.0)
    far = np.flatnonzero(out > 0.05)
    if far.size:
        dl = np.linspace(-window_l, window_l, 25)
        Lw = np.clip(L[far, None] + dl, 0.0, 100.0)
        cw = oracle(Lw.ravel(), np.repeat(h[far], dl.size)).reshape(Lw.shape)
        out[far] = np.min(np.hypot(Lw - L[far, None], np.maximum(C[far, None] - cw, 0.0)), axis=1)
    return out


def test_mapped_colours_lie_in_the_true_gamut(process_separator):
    """The perceptual mapping's targets (a 13³ grid of sRGB) lie in the print's gamut as a brute
    force finds it (tests/oracles.py: the faces of the coverage polytope, sampled independently,
    located in each colour's hue slice), also where the gamut is concave in the slice (the
    yellow-greens above their cusp, where a convex hull per slice put 16 % of a 17³ table's
    nodes up to ΔE76 2.3 outside). The oracle is checked too: no separated colour lies outside it."""
    from solver.apps.separation.colour_space import srgb_to_lab

    sep = process_separator
    tac = sep.objective.rule.tac
    axis = np.linspace(0.0, 1.0, 13)
    rgb = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    targets = sep.targets(srgb_to_lab(rgb, sep.model.measurement))
    miss = _outside_true_gamut(sep.model, tac, targets)
    assert np.mean(miss > 0.5) < 0.01 and miss.max() < 1.0, (np.mean(miss > 0.5), miss.max())
    printed, _ = sep.separate_srgb(rgb[::7])                    # colours on the gamut's boundary too
    assert _outside_true_gamut(sep.model, tac, printed.printed_lab).max() < 0.1   # the oracle bounds the print


def test_colours_well_inside_are_left_alone(ryb, ryb_boundary):
    """Printable colours of mid lightness near the neutral axis (well within the knee) are
    printed as they are."""
    from solver.apps.separation.gamut import to_lch

    rng = np.random.default_rng(8)
    lab = ryb.lab(rng.uniform(0.0, 0.6, (4000, 3)))
    L, C, h = to_lch(lab)
    lab = lab[(L > 30) & (L < 70) & (C < 0.3 * ryb_boundary.chroma_max(h, L))][:200]
    assert len(lab) >= 50
    src = lab.copy()
    src[:, 0] = ryb_boundary.lightness_unmap(lab[:, 0])                  # undo the L* compression
    # atol: the perceived hue is kept at the compensated L*, which moves a*, b* by up to ~1e-3
    np.testing.assert_allclose(map_to_gamut(src, ryb_boundary, GamutSettings(knee=0.8)), lab, atol=5e-3)


# ------------------------------------------------------------------ black generation and TAC
def test_black_found_and_named(ryb, rybk):
    assert find_black(ryb) is None and find_black(rybk) == 3
    assert black_index(rybk, RYBK, "none") is None and black_index(rybk, RYBK, "R30") == 0
    with pytest.raises(ValueError, match="not one of the inks"):
        black_index(rybk, RYBK, "K100")


def test_gcr_puts_black_in_greys_and_respects_the_tac(rybk, rybk_separator):
    """Neutral ramp: more black the darker (K rises monotonically past the black start), less
    chromatic ink than without black (strength 0), the colour matched; random colours never
    exceed the total area coverage limit."""
    black = 3
    results = {}
    for strength in (0.0, 0.7, 1.0):
        sep_ = rybk_separator.with_rule(BlackGeneration(strength=strength))
        results[strength] = sep_.separate_srgb(np.repeat(np.linspace(0, 1, 18)[:, None], 3, 1))[0]
    k = results[0.7].coverages[:, black]
    assert np.all(np.diff(k) <= 1e-6) and k[0] > 0.5 and k[-1] < 1e-3          # white → no black
    assert results[0.0].coverages[:, black].max() < k.max()
    cmy = lambda r: r.coverages[:, :3].sum(axis=1)                              # noqa: E731
    assert np.all(cmy(results[1.0]) <= cmy(results[0.0]) + 1e-3)
    assert cmy(results[1.0])[2] < 0.7 * cmy(results[0.0])[2]
    for r in results.values():
        assert r.coverages.sum(axis=1).max() <= 3.0 + 1e-9
        assert np.median(r.delta_e76) < 1e-2
    rng = np.random.default_rng(1)
    sep_ = rybk_separator.with_rule(BlackGeneration(tac=2.4))
    sep, _ = sep_.separate_srgb(rng.random((300, 3)))
    assert sep.coverages.sum(axis=1).max() <= 2.4 + 1e-9


def test_black_aim_rules():
    rule = BlackGeneration(strength=0.8, start=0.25)
    kn = np.linspace(0, 1, 101)
    aim = rule.aim(kn, np.ones_like(kn))
    assert np.all(aim[kn <= 0.25] == 0) and np.all(np.diff(aim) >= 0) and aim[-1] == pytest.approx(0.8)
    assert np.all(rule.aim(kn, np.full_like(kn, 0.5)) <= aim)
    ucr = BlackGeneration("ucr", strength=0.8, start=0.25)
    assert ucr.aim(np.array([0.9]), np.array([0.7]))[0] < rule.aim(np.array([0.9]), np.array([0.7]))[0]
    for bad in (dict(mode="max"), dict(strength=1.5), dict(strength=-0.1), dict(start=1.0), dict(tac=4.5),
                dict(tac=0.5)):
        with pytest.raises(BlackGenerationError) as info:        # a ValueError naming the field
            BlackGeneration(**bad)
        assert isinstance(info.value, ValueError) and info.value.field == next(iter(bad))
        assert info.value.value == next(iter(bad.values()))
    for edge in (dict(strength=0.0), dict(strength=1.0), dict(start=0.0), dict(tac=1.0), dict(tac=4.0)):
        BlackGeneration(**edge)                                   # the ranges' closed ends


def test_objective_k_neutral_inverts_the_black_ramp(rybk):
    obj = InkingObjective.build(rybk, 3)
    k = np.linspace(0, 1, 11)
    c = np.zeros((11, 4))
    c[:, 3] = k
    np.testing.assert_allclose(obj.k_neutral(rybk.lab(c)[:, 0]), k, atol=2e-3)


# ------------------------------------------------------------------ the separation table
def test_tetrahedral_lut_is_exact_on_linear_tables():
    """Tetrahedral interpolation reproduces any affine function of the colour exactly (its
    defining property), and the table's nodes exactly."""
    n = 5
    axis = np.linspace(0, 1, n)
    rgb = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1)
    A = np.array([[0.3, -0.2, 0.1, 0.05], [0.1, 0.4, -0.3, 0.2], [-0.25, 0.15, 0.5, 0.1]])
    lut = SeparationLUT(n, rgb @ A + 0.1)
    x = np.random.default_rng(0).random((1000, 3))
    np.testing.assert_allclose(lut(x), x @ A + 0.1, atol=1e-12)
    np.testing.assert_allclose(lut(rgb.reshape(-1, 3)), (rgb @ A + 0.1).reshape(-1, 4), atol=1e-12)


def test_lut_error_against_direct_separation(ryb, ryb_separator):
    """A 17³ table against separating every colour: printed ΔE2000 small on random colours."""
    sep_ = ryb_separator
    lut, _ = SeparationLUT.build(sep_, 17)
    x = np.random.default_rng(3).random((400, 3))
    direct, _ = sep_.separate_srgb(x)
    de = delta_e2000(ryb.lab(lut(x)), direct.printed_lab)
    assert np.median(de) < 0.5 and np.percentile(de, 95) < 2.0


# ------------------------------------------------------------------ characterisation (CGATS)
def read_cgats(text: str):
    """The test's own CGATS.17 reader: (keywords, field names, rows of strings)."""
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    assert lines[0].startswith("CGATS")
    keywords, fields, rows, section = {}, None, [], None
    for ln in lines[1:]:
        word = ln.split()[0]
        if word in ("BEGIN_DATA_FORMAT", "BEGIN_DATA"):
            section = word
        elif word in ("END_DATA_FORMAT", "END_DATA"):
            section = None
        elif section == "BEGIN_DATA_FORMAT":
            fields = ln.split()
        elif section == "BEGIN_DATA":
            rows.append(ln.split())
        else:
            key, _, value = ln.partition("\t")
            keywords[key] = value.strip().strip('"')
    return keywords, fields, rows


def test_characterisation_chart_parses(rybk):
    from solver.apps.separation.characterisation import characterisation_text, process_order

    text = characterisation_text(rybk, RYBK, black=3, created="2026-01-01T00:00:00Z")
    keywords, fields, rows = read_cgats(text)
    assert fields == ["SAMPLE_ID", "CMYK_C", "CMYK_M", "CMYK_Y", "CMYK_K", "XYZ_X", "XYZ_Y", "XYZ_Z",
                      "LAB_L", "LAB_A", "LAB_B"]
    assert int(keywords["NUMBER_OF_FIELDS"]) == len(fields) and int(keywords["NUMBER_OF_SETS"]) == len(rows)
    assert "Illumination=D50" in keywords["MEASUREMENT_SOURCE"] and "WhiteBase=Abs" in keywords["MEASUREMENT_SOURCE"]
    data = np.array([[float(v) for v in r] for r in rows])
    assert len(rows) > 1300 and all(len(r) == len(fields) for r in rows)
    assert len({tuple(r[1:5]) for r in rows}) == len(rows)                      # distinct patches
    order = process_order(rybk, RYBK, 3)
    assert order == [2, 0, 1, 3]                                    # B30 plays cyan, R30 magenta, Y30 yellow
    paper = data[(data[:, 1:5] == 0).all(axis=1)][0]
    np.testing.assert_allclose(paper[8:11], rybk.absolute_lab(np.zeros(4)), atol=1e-3)
    k_ramp = data[(data[:, 1:4] == 0).all(axis=1)]
    k_ramp = k_ramp[np.argsort(k_ramp[:, 4])]
    assert np.all(np.diff(k_ramp[:, 8]) < 0)                        # more black, darker
    # XYZ and Lab agree (CIE 15 formulae, the white being the perfect diffuser of D50)
    import colour
    white = colour.XYZ_to_xy(rybk.absolute_white_xyz)
    np.testing.assert_allclose(colour.XYZ_to_Lab(data[:, 5:8] / 100.0, white), data[:, 8:11], atol=1e-2)  # 4 decimals


def test_dark_reds_that_need_much_black_are_reached():
    """Dark reds of a photograph's shadows (sRGB R 64–76, G 14–22, B 18–24), printed with the
    process inks as AM dots (Murray–Davies): printable with K ≈ 0.9 under M and Y, but their
    black aim is near 0 (saturated), and the black-aimed pass ends at K ≈ 0.07 under C, M, Y
    with the colour up to ΔE76 2.5 away (55 of these 120 colours). The colour-first pass must
    reach every one of them."""
    from solver.apps.separation import PrintSettings
    from solver.apps.separation.halftone import parse_dots
    from solver.apps.separation.job import build_separator
    from solver.apps.separation.printset import parse_ink_list

    settings = PrintSettings(inks=parse_ink_list("process"), dots=parse_dots("AM:20"))
    sep = build_separator(settings, printed_inks(settings.inks))
    srgb = np.stack(np.meshgrid(np.arange(64, 80, 3), np.arange(14, 23, 2), np.arange(18, 25, 2), indexing="ij"),
                    -1).reshape(-1, 3) / 255.0
    result, _ = sep.separate_srgb(srgb)
    assert np.max(result.delta_e76) < sep.solver.gamut_de, np.sort(result.delta_e76)[-5:]
    assert np.median(result.coverages[:, sep.objective.black]) > 0.5      # the black does it
