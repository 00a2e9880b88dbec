"""`ink-tables geometry`: summary, pictures, and one clear error line for bad input."""

import matplotlib.image
import numpy as np

from solver.cli import main
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
