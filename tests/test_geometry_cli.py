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
    grains (count, fractions, clusters, pair correlation) and voxel fractions as the tables'
    own geometry unit, for the default and another --table-seed; other seeds differ."""
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
        argv = ["geometry", "--ink", "Y15", "--particles", "sphere:300", "--realization", str(k),
                "--grid", *map(str, req.wave.grid)] + ([] if table_seed is None else ["--table-seed", str(table_seed)])
        assert main(argv) == 0
        out = capsys.readouterr().out
        assert lines(out) == lines(summary(real, vox)), (table_seed, k)
        assert f"realization {k} of the tables with --seed {req.wave.seed}" in out
    assert main(["geometry", "--ink", "Y15", "--particles", "sphere:300", "--seed", "0",
                 "--grid", *map(str, req.wave.grid)]) == 0
    assert lines(capsys.readouterr().out) != lines(summary(real, vox))
    for argv, words in ((["--table-seed", "3"], "--realization"), (["--realization", "-1"], "count from 0"),
                        (["--realization", "0", "--table-seed", "-3"], "--table-seed -3"),
                        (["--realization", "1", "--seed", "2"], "not allowed with")):
        try:
            rc = main(["geometry", "--ink", "Y15", "--particles", "sphere:300"] + argv)
        except SystemExit as exc:
            rc = exc.code
        err = capsys.readouterr().err
        assert rc == 2 and words in err, (argv, err)
