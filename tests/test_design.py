"""`ink-tables design` and solver.design: the ISO 12647-2 aims against the standard's numbers,
a known recipe found back from its own colour, the paper white analytically, overprints against
a stack built directly, bad input in one line before any work, and the package's process inks
against the colours they were designed to."""

import json

import numpy as np
import pytest

from conftest import run_main
from solver.apps.cli import main
from solver.colour.aims import AIMS, ISO12647_2_PC1, AimError, parse_aim
from solver.colour.cie import delta_e2000
from solver.colour.measurement import DEFAULT
from solver.design import FilmColour, InkTemplate, Recipe, design_ink, design_paper
from solver.design.optimise import bound_names
from solver.design.recipe import DesignError
from solver.inks import parse_ink
from solver.printing.process_inks import process_inks, process_paper_albedo
from solver.table.request import table_request
from solver.table.thinfilm_tier import build_stack_table

#: ISO 12647-2:2004/Amd 1:2007, paper type 1 (FOGRA39), CIELAB D50/2°, black backing — the
#: standard's table, typed here independently of solver/colour/aims.py
STANDARD = {"paper": (95, 0, -2), "cyan": (55, -37, -50), "magenta": (48, 74, -3), "yellow": (89, -5, 93),
            "black": (16, 0, 0), "red": (47, 68, 48), "green": (50, -65, 27), "blue": (24, 22, -46)}
OVERPRINTS = {"red": {"magenta", "yellow"}, "green": {"cyan", "yellow"}, "blue": {"cyan", "magenta"}}


def test_aims_are_the_standards_numbers():
    assert {a.colour for a in ISO12647_2_PC1.values()} == set(STANDARD)
    for colour, lab in STANDARD.items():
        aim = AIMS[f"iso12647-2:PC1:{colour}"]
        assert aim.lab == lab
        assert set(aim.inks) == OVERPRINTS.get(colour, set() if colour == "paper" else {colour})
    assert len(parse_aim("iso12647-2")) == 8 and parse_aim("ISO12647-2:pc1:cyan")[0].colour == "cyan"
    custom = parse_aim(" 50, 10,-20")[0]
    assert custom.lab == (50.0, 10.0, -20.0) and custom.kind == "custom"


@pytest.mark.parametrize("text, words", [("iso12647-2:PC1:magent", ["known aims:", "iso12647-2:PC1:magenta"]),
                                         ("50,10", ["not a known aim"]), ("120,0,0", ["0 ≤ L* ≤ 100"])])
def test_bad_aims_are_one_line(text, words):
    with pytest.raises(AimError) as info:
        parse_aim(text)
    assert "\n" not in str(info.value) and all(w in str(info.value) for w in words)


def test_design_finds_a_known_recipe_back():
    """A film of known load and thickness; its 45:0 colour as the aim: design finds it back."""
    colour = FilmColour(paper=0.85)
    known = Recipe((("C", 0.12),), 900.0)
    aim = parse_aim(",".join(f"{v:.6f}" for v in colour.lab(known)))[0]
    result = design_ink(aim, InkTemplate(("C",)), colour)
    assert result.de2000 < 0.1 and result.reached and result.at_bounds == []
    # with the thickness fixed, the load itself is found (ΔE is monotone in the load)
    fixed = design_ink(aim, InkTemplate(("C",), thickness_range_nm=(900.0, 900.0)), colour)
    assert fixed.de2000 < 0.01 and fixed.recipe.loads[0][1] == pytest.approx(0.12, abs=1e-4)


def test_an_aim_out_of_reach_names_the_bound():
    colour = FilmColour(paper=0.9)
    aim = parse_aim("30,80,-60")[0]                      # a deep violet from the yellow pigment
    result = design_ink(aim, InkTemplate(("Y",), thickness_range_nm=(1000.0, 1000.0)), colour)
    assert not result.reached and result.de2000 > 30
    assert result.at_bounds == ["load Y = 0 % (lower bound 0 %)"]
    # the thickness the caller fixed is a limit too, named with the option that fixed it
    assert result.fixed == ["thickness fixed at 1000 nm by --thickness-range"]
    assert result.limits == result.fixed + result.at_bounds


def test_a_load_stopped_just_short_of_its_cap_is_named_and_is_the_limit():
    """The cyan aim with the load capped at 3 %: the optimiser stops a hair short of the cap
    (2.99 %), which is at that bound; and it is what limits: a higher cap does better."""
    colour = FilmColour(paper=0.8762)
    aim = AIMS["iso12647-2:PC1:cyan"]
    capped = design_ink(aim, InkTemplate(("C",), load_range=(0.0, 0.03)), colour)
    assert not capped.reached and capped.fixed == []
    assert len(capped.at_bounds) == 1 and capped.at_bounds[0].startswith("load C = ")
    assert capped.at_bounds[0].endswith("(upper bound 3 %)")
    wider = design_ink(aim, InkTemplate(("C",), load_range=(0.0, 0.04)), colour)
    assert wider.de2000 < capped.de2000 - 0.1
    # a parameter well inside its range is not at a bound
    assert bound_names(["load C"], [0.027], [(0.0, 0.03)]) == []


def test_fixed_loads_and_thickness_design_the_one_recipe():
    """--load-range 5 fixes every load (as --thickness-range 1000 fixes the thickness): the
    thickness alone is free; with both fixed the result is that one film, measured directly."""
    template = InkTemplate(("C", "M"), load_range=(0.05, 0.05))
    assert template.names == ("thickness_nm",) and template.fixed == [
        "load C fixed at 5 % by --load-range", "load M fixed at 5 % by --load-range"]
    colour = FilmColour(paper=0.88)
    aim = AIMS["iso12647-2:PC1:cyan"]
    free_thickness = design_ink(aim, template, colour)
    assert dict(free_thickness.recipe.loads) == {"C": 0.05, "M": 0.05}
    one = design_ink(aim, InkTemplate(("C",), load_range=(0.05, 0.05), thickness_range_nm=(800.0, 800.0)), colour)
    film = Recipe((("C", 0.05),), 800.0)
    assert one.recipe == film and one.at_bounds == [] and len(one.fixed) == 2
    assert one.de2000 == pytest.approx(float(delta_e2000(colour.lab(film), np.asarray(aim.lab))), abs=1e-9)


def test_an_aim_best_met_by_bare_paper_is_found_at_the_bound():
    """50/100/100 with the cyan pigment only: every cyan load moves away from it, so the best
    recipe is bare paper (load 0), whose colour is computed here directly; an interior local
    minimum (ΔE2000 52.3 at the upper bound, as a grid inside the box found) must not win."""
    colour = FilmColour(paper=0.88)
    aim = parse_aim("50,100,100")[0]
    result = design_ink(aim, InkTemplate(("C",)), colour)
    paper_only = colour.lab(Recipe((("C", 0.0),), 1000.0))
    assert result.de2000 <= float(delta_e2000(paper_only, np.asarray(aim.lab))) + 1e-6
    assert result.at_bounds[0].startswith("load C = 0 %")


def test_the_paper_white_matches_l_star_analytically():
    """A flat albedo r is neutral with Y = r: the best one for 95/0/−2 has L* = 95 exactly."""
    aim = AIMS["iso12647-2:PC1:paper"]
    colour = FilmColour()
    result = design_paper(aim, colour, colour.wavelengths_nm)
    assert result.paper == pytest.approx(((95.0 + 16.0) / 116.0) ** 3, abs=1e-5)
    np.testing.assert_allclose(result.lab, [95.0, 0.0, 0.0], atol=1e-4)
    assert result.de2000 == pytest.approx(float(delta_e2000(np.array([95.0, 0, 0]), np.array([95.0, 0, -2]))))


def test_an_overprint_is_the_stack_in_printing_order():
    """print_lab((M, Y)) = the colour of Y printed over M, a stack built directly."""
    colour = FilmColour(paper=0.88)
    m, y = Recipe((("M", 0.2),), 700.0), Recipe((("Y", 0.15),), 800.0)
    wl, sigma = colour.wavelengths_nm, np.asarray(table_request("Y10").grids.sigma_rad)
    materials = table_request("Y10").layer_materials(0)
    stack = build_stack_table([(parse_ink("Y15"), 800.0), (parse_ink("M20"), 700.0)], wl, sigma, materials)
    np.testing.assert_allclose(colour.print_lab((m, y)), DEFAULT.lab(stack, 0.88), atol=1e-9)
    assert float(delta_e2000(colour.print_lab((m, y)), colour.print_lab((y, m)))) > 0.1   # order matters


def test_templates_refuse_bad_ranges_and_pigments():
    with pytest.raises(DesignError, match="--pigments 'Q'"):
        InkTemplate.of("Q")
    with pytest.raises(DesignError, match="--load-range"):
        InkTemplate(("C",), load_range=(0.3, 0.2))
    with pytest.raises(DesignError, match="--load-range.*lower MIN"):
        InkTemplate(("C", "M", "Y"), load_range=(0.4, 0.4))
    with pytest.raises(DesignError, match="--thickness-range"):
        InkTemplate(("C",), thickness_range_nm=(0.0, 100.0))
    assert InkTemplate.of("K+C+M").names == ("load K", "load C", "load M", "thickness_nm")


@pytest.mark.parametrize("argv, words", [
    (["--aim", "iso12647-2:PC1:cyn"], ["known aims:", "iso12647-2:PC1:cyan"]),
    (["--aim", "40,60,0"], ["--pigments"]),
    (["--aim", "iso12647-2", "--pigments", "C"], ["--pigments", "one ink"]),
    (["--aim", "iso12647-2:PC1:cyan", "--load-range", "20,10"], ["--load-range"]),
    (["--aim", "iso12647-2:PC1:cyan", "--thickness-range", "x"], ["--thickness-range"]),
    (["--aim", "iso12647-2:PC1:cyan", "--geometry", "45/0"], ["45:0"]),
    (["--aim", "iso12647-2:PC1:cyan", "-o", "out.txt"], ["must end in .json"]),
    (["--aim", "iso12647-2:PC1:cyan", "--paper", "1.5"], ["--paper"]),
])
def test_bad_input_is_one_line_before_any_work(argv, words, capsys, monkeypatch):
    import solver.design as design

    def no_work(*a, **k):
        raise AssertionError("work started")

    monkeypatch.setattr(design, "design_ink", no_work)
    monkeypatch.setattr(design, "design_process_set", no_work)
    code, out, err = run_main(main, ["design"] + argv, capsys)
    assert code == 2 and err.count("\n") == 1 and err.startswith("ink-tables design: error:")
    assert all(w in err for w in words), err


def test_cli_prints_the_recipe_and_writes_the_json(tmp_path, capsys):
    out_path = tmp_path / "cyan.json"
    code, out, err = run_main(main, ["design", "--aim", "iso12647-2:PC1:cyan", "--paper", "0.8762",
                                     "--thickness-range", "540", "-o", str(out_path)], capsys)
    assert code == 0, err
    assert "recipe  C" in out and "ΔE2000" in out and "film tables" in out
    doc = json.loads(out_path.read_text())
    entry = doc["aims"]["cyan"]
    assert set(entry) >= {"recipe", "lab", "aim", "de2000"} and entry["aim"] == [55.0, -37.0, -50.0]
    assert entry["recipe"]["thickness_nm"] == 540.0 and entry["de2000"] < 3.0
    assert doc["command"] == "ink-tables design --aim iso12647-2:PC1:cyan --thickness-range 540 --paper 0.8762"
    assert entry["fixed"] == ["thickness fixed at 540 nm by --thickness-range"]
    # the recipe printed is the recipe written: its colour measured again
    recipe = Recipe(tuple((c, p / 100) for c, p in entry["recipe"]["loads_percent"].items()), 540.0)
    assert float(delta_e2000(FilmColour(paper=0.8762).lab(recipe), np.array(entry["lab"]))) < 0.01


def _stderr_before_any_work(capsys, monkeypatch, *options) -> str:
    """What `ink-tables design --aim 50,-30,-40 --pigments C OPTIONS` says on stderr before its
    design would start (the design itself replaced by a stop)."""
    import solver.design as design

    def no_work(*a, **k):
        raise AssertionError("work started")

    monkeypatch.setattr(design, "design_ink", no_work)
    with pytest.raises(AssertionError, match="work started"):
        main(["design", "--aim", "50,-30,-40", "--pigments", "C", *options])
    return capsys.readouterr().err


def test_a_thickness_range_in_micrometres_is_warned_of_once_before_any_work(capsys, monkeypatch):
    """--thickness-range 0.5,2 (µm typed as nm): the thin-layer rule of the tables
    (request_checks.thin_layers_warning), said once for --thickness-range before the design
    starts, and not again for each film the design computes."""
    import warnings

    err = _stderr_before_any_work(capsys, monkeypatch, "--thickness-range", "0.5,2")
    assert err.startswith("warning: --thickness-range 0.5, 2: a layer thinner than 50 nm") and err.count("\n") == 1, err
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        FilmColour().lab(Recipe((("C", 0.1),), 2.0))
    assert not caught, [str(w.message) for w in caught]


def test_a_particle_design_says_what_it_will_build_before_any_work(capsys, monkeypatch):
    """--particles: one line up front with the preflight's estimate of a table and how many
    tables the design reads or builds at most (a particle design otherwise runs silently)."""
    from solver.design.optimise import PARTICLE_TABLES

    err = _stderr_before_any_work(capsys, monkeypatch, "--particles", "sphere:100")
    assert err.count("\n") == 1, err
    assert err.startswith(f"--particles sphere:100: up to {PARTICLE_TABLES} particle tables per ink"), err
    assert "each estimated table" in err and "wave solves, ≈ " in err and "worker" in err, err


def test_cli_one_value_fixes_either_range_and_is_named_as_the_limit(capsys):
    """--load-range 5 fixes the loads as --thickness-range 1000 fixes the thickness (the help
    says so for both); an aim out of reach names them, with their options, as its limits."""
    code, out, err = run_main(main, ["design", "--aim", "iso12647-2:PC1:cyan", "--paper", "0.8762", "--load-range",
                                     "5", "--thickness-range", "1000", "--tolerance", "0.5"], capsys)
    assert code == 0, err
    assert "recipe  C5@1000nm" in out
    assert ("limited by: load C fixed at 5 % by --load-range; thickness fixed at 1000 nm by --thickness-range"
            in out), out
    code, out, _ = run_main(main, ["design", "--help"], capsys)
    help_text = " ".join(out.split())
    assert "pigment load (volume percent); one value fixes every load" in help_text
    assert "thickness (nm); one value fixes it" in help_text


def test_the_package_process_inks_print_their_recorded_colours():
    """Each process ink of the package data, measured again on its paper: the recorded colour,
    and within ΔE2000 3 of the standard's solid."""
    inks = process_inks()
    assert [i.colour for i in inks] == ["black", "cyan", "magenta", "yellow"]
    colour = FilmColour(paper=process_paper_albedo())
    for ink in inks:
        recipe = Recipe(parse_ink(ink.spec).components, ink.thickness_nm)
        lab = colour.lab(recipe)
        assert float(delta_e2000(lab, np.array(ink.lab))) < 0.02, ink
        assert float(delta_e2000(lab, np.array(STANDARD[ink.colour]))) <= 3.0, ink


class _OffsetParticles(FilmColour):
    """A stand-in for particle tables (a wave table per recipe costs minutes): the molecular
    colour plus a smooth offset that depends on the recipe, as grains shift a colour."""

    def lab(self, recipe):
        from dataclasses import replace

        lab = super().lab(replace(recipe, particles="molecular"))
        if recipe.particles == "molecular":
            return lab
        self.wave_tables += 1
        load = recipe.loads[0][1]
        return lab + np.array([4.0 - 10.0 * load, -3.0 + 5.0 * load, 2.0 + recipe.thickness_nm / 1000.0])


def test_a_particle_ink_is_designed_through_a_few_tables():
    colour = _OffsetParticles(paper=0.88)
    known = Recipe((("C", 0.10),), 800.0, "sphere:100")
    aim = parse_aim(",".join(f"{v:.6f}" for v in colour.lab(known)))[0]
    colour.wave_tables = 0
    result = design_ink(aim, InkTemplate(("C",), particles="sphere:100"), colour, tolerance=0.02)
    assert result.de2000 < 0.1 and result.recipe.particles == "sphere:100"
    assert result.particle_tables == colour.wave_tables <= 4
    # the molecular design of the same aim is off by the grains' offset
    assert design_ink(aim, InkTemplate(("C",)), FilmColour(paper=0.88)).recipe.loads != result.recipe.loads


def test_particle_overprints_are_refused(capsys):
    code, out, err = run_main(main, ["design", "--aim", "iso12647-2", "--particles", "sphere:100"], capsys)
    assert code == 2 and "--particles" in err and "overprints" in err
