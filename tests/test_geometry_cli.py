"""`ink-tables geometry`: summary, pictures, and one clear error line for bad input."""

import matplotlib.image
import numpy as np

from solver.apps.cli import main
from solver.materials import PIGMENT_DISPLAY_RGB

SMALL = ["--cell", "800", "--thickness", "500", "--grid", "32", "32", "20"]


def test_geometry_summary_and_picture(tmp_path, capsys):
    png = tmp_path / "sections.png"
    rc = main(["geometry", "--ink", "Y7.5+B7.5", "--particles", "sphere:100:agglutinated", "--seed", "4",
               "--png", str(png)] + SMALL)
    out = capsys.readouterr().out
    assert rc == 0
    assert "Y: " in out and "B: " in out and "volume fraction 7.5000%" in out
    assert "overlapping pairs: 0" in out and "clusters" in out and "agglutination" in out
    image = matplotlib.image.imread(png)[..., :3]
    # Both pigments' display colours appear in the picture.
    for code in ("Y", "B"):
        colour = np.array(PIGMENT_DISPLAY_RGB[code])
        assert (np.abs(image - colour).max(axis=-1) < 0.02).sum() > 50, code


def test_geometry_bad_input_gives_one_error_line(capsys):
    for args, words in [
        (["--ink", "B15", "--particles", "cylinder:100:diagonal"], ["unknown particle modifier", "diagonal"]),
        (["--ink", "B70", "--particles", "sphere:100"], ["reachable limit"]),
        (["--ink", "B15", "--particles", "sphere:-20"], ["negative particle size"]),
        (["--ink", "B15", "--particles", "sphere:600"], ["larger than the layer"]),
        (["--ink", "clear", "--particles", "sphere:100"], ["'clear' has no pigment to make grains of"]),
        (["--ink", "Y15/B15", "--particles", "sphere:100"], ["draws one layer", "--ink Y15"]),
    ]:
        rc = main(["geometry"] + args + SMALL)
        err = capsys.readouterr().err.strip()
        assert rc == 2 and err.count("\n") == 0 and err.startswith("ink-tables geometry: error:")
        for word in words:
            assert word in err


def test_molecular_has_no_geometry(capsys, tmp_path):
    """Asking for the geometry of a molecular ink is refused (there is none), and no picture is
    silently left unwritten."""
    assert main(["geometry", "--ink", "G30", "--particles", "molecular", "--png", str(tmp_path / "g.png")]) == 2
    err = capsys.readouterr().err
    assert "homogeneous" in err and "--particles" in err and not (tmp_path / "g.png").exists()


def test_realization_draws_the_cell_a_table_solves(capsys):
    """--realization K shows the very cell realization K of the tables was solved on: the same
    grains (count, fractions, clusters, pair correlation) and voxel fractions — on the tables'
    grid, without --grid — as the tables' own geometry unit, for the default and another
    --table-seed; other seeds differ."""
    from solver.geometry import generate
    from solver.geometry.report import summary
    from solver.table import wave_tier
    from solver.table.request import table_request

    def lines(text):            # the grains and voxels, not the timing of the placement
        return [l for l in text.splitlines() if not l.startswith(("layer ", "placement", "realization "))]

    for table_seed, k in ((None, 0), (None, 2), (7, 1)):
        req = table_request("Y15", "sphere:300", **({} if table_seed is None else {"seed": table_seed}))
        vox = wave_tier.geometry_unit(wave_tier.GeometryUnit(req, k))
        real = generate(wave_tier.layer_spec(req), wave_tier.realization_seed(req, k))
        argv = ["geometry", "--ink", "Y15", "--particles", "sphere:300", "--realization", str(k)] + (
            [] if table_seed is None else ["--table-seed", str(table_seed)])      # the tables' grid by default
        assert main(argv) == 0
        out = capsys.readouterr().out
        assert lines(out) == lines(summary(real, vox)), (table_seed, k)
        assert f"realization {k} of the tables built with seed {req.wave.seed} (--table-seed" in out
        assert f"on the default tables' voxel grid {'×'.join(map(str, req.wave.grid))}" in out
    assert main(["geometry", "--ink", "Y15", "--particles", "sphere:300", "--seed", "0",
                 "--grid", *map(str, req.wave.grid)]) == 0
    assert lines(capsys.readouterr().out) != lines(summary(real, vox))
    for argv, words in ((["--table-seed", "3"], "--realization"), (["--realization", "-1"], "count from 0"),
                        (["--realization", "0", "--table-seed", "-3"], "--table-seed: give an integer in [0, 2^32), got -3"),
                        (["--seed", "4294967296"], "--seed: give an integer in [0, 2^32)"),
                        (["--realization", "1", "--seed", "2"], "not allowed with")):
        try:
            rc = main(["geometry", "--ink", "Y15", "--particles", "sphere:300"] + argv)
        except SystemExit as exc:
            rc = exc.code
        err = capsys.readouterr().err
        assert rc == 2 and words in err, (argv, err)


# ------------------------------------------------------------------ preflight (as `build`'s)
def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("ink-tables geometry: error:"), err
    return err


def test_a_cell_that_cannot_fit_is_refused_before_any_work(capsys):
    """Grains far too many (sphere:1 at R15: ~10⁹) or a grid far too large: one line naming
    the estimate and geometry's own options, in well under a second (no generation)."""
    import time

    for args, need in ((["--particles", "sphere:1"], "1,145,915,590 grains"),
                       (["--particles", "sphere:100", "--grid", "4096", "4096", "4096"], "4096×4096×4096")):
        t0 = time.perf_counter()
        assert main(["geometry", "--ink", "R15"] + args) == 2
        assert time.perf_counter() - t0 < 2.0
        err = _one_error_line(capsys)
        assert "refused before starting" in err and need in err and "of memory" in err
        assert "--grid" in err and "--force" in err
        assert "--wavelengths" not in err and "--workers" not in err       # options geometry lacks


def test_the_memory_limit_is_this_machines(capsys, monkeypatch):
    """The refusal compares the estimate with the machine's available memory (solver.host): the
    same small cell is refused on a machine with 10 MB, generated there with --force, and
    generated without on a machine with the tests' memory."""
    from solver import host
    from solver.geometry import LayerSpec, geometry_cost, parse_particles
    from solver.inks import parse_ink

    args = ["geometry", "--ink", "R15", "--particles", "sphere:150"] + SMALL
    need = geometry_cost(LayerSpec(parse_ink("R15"), parse_particles("sphere:150"), thickness_nm=500.0,
                                   cell_nm=(800.0, 800.0)), (32, 32, 20)).peak_bytes
    assert main(args) == 0 and "volume fraction" in capsys.readouterr().out
    monkeypatch.setattr(host, "available_memory_bytes", lambda: 0.5 * need)
    assert main(args) == 2 and "refused before starting" in _one_error_line(capsys)
    assert main(args + ["--force"]) == 0 and "volume fraction" in capsys.readouterr().out


def test_grains_the_grid_does_not_resolve_and_a_long_cell_are_warned(capsys, caplog, monkeypatch):
    import logging

    from solver.table import preflight

    monkeypatch.setattr(preflight, "LONG_BUILD_S", 0.0)
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        assert main(["geometry", "--ink", "R15", "--particles", "sphere:12", "--cell", "400", "--thickness",
                     "200", "--grid", "8", "8", "4"]) == 0
    assert "much smaller than the 50-nm voxels" in caplog.text and "--grid" in caplog.text
    assert "will take long" in caplog.text and "grains" in caplog.text


def test_out_of_memory_names_geometrys_own_options(capsys, monkeypatch):
    """Memory running out anyway (a forced cell) is one line whose advice names options that
    geometry has."""
    import solver.geometry

    def exhausted(*_a, **_k):
        raise MemoryError("Unable to allocate 512. GiB")

    monkeypatch.setattr(solver.geometry, "generate", exhausted)
    assert main(["geometry", "--ink", "R15", "--particles", "sphere:100", "--force"] + SMALL) == 1
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "ran out of memory" in err and "--grid" in err
    assert "--wavelengths" not in err and "--workers" not in err


def test_a_grid_without_voxels_is_refused(capsys):
    assert main(["geometry", "--ink", "R15", "--particles", "sphere:100", "--grid", "0", "4", "4"]) == 2
    assert "--grid 0 4 4" in _one_error_line(capsys)
