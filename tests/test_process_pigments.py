"""The process pigments C, M, K (solver/data/pigments_nk.csv): derived values against the raw
refractiveindex.info rows, each pigment's own measured n, and the paper's R/Y/B unchanged."""

import dataclasses

import numpy as np
import pytest

from solver.data.derive_pigments import GRID_NM, read_database_nk
from solver.inks import molecular_eps, parse_ink
from solver.materials import (PIGMENT_REAL_INDEX, PIGMENTS, default_materials, load_material_data,
                              pigment_eps)
from solver.table.request import table_request
from solver.table.thinfilm_tier import build_thinfilm_table

# Raw rows (λ µm, n, k) copied by hand from the refractiveindex.info database (commit ff11b589):
SQIB_450 = {"alpha": (1.12243, 0.06148), "beta": (1.30146, 0.05941), "gamma": (1.39770, 0.07751)}
SQIB_600 = {"alpha": (0.83672, 2.06128), "beta": (0.61141, 0.45927), "gamma": (1.03871, 0.46806)}
R6G = {450.0: (1.322504, 0.130146), 550.0: (2.189085, 0.650763), 600.0: (2.075739, 0.034352)}
#: Arakawa.yml rows bracketing 415 nm and 540 nm: (µm, n, k)
ARAKAWA = [(0.4133, 2.11, 0.90), (0.4428, 2.17, 0.89), (0.5166, 2.30, 0.87), (0.5636, 2.38, 0.82)]


def _lerp(rows, wl_nm, col):
    x = [1000.0 * r[0] for r in rows]
    return float(np.interp(wl_nm, x, [r[col] for r in rows]))


def test_cyan_is_the_mean_of_the_three_sqib_axes_and_held_below_450_nm():
    data = default_materials()
    for wl, rows in ((450.0, SQIB_450), (600.0, SQIB_600)):
        n = np.mean([v[0] for v in rows.values()])
        k = np.mean([v[1] for v in rows.values()])
        assert data.pigment_n("C", wl) == pytest.approx(n, abs=2e-6)
        assert data.pigment_k("C", wl) == pytest.approx(k, abs=2e-6)
    # the data start at 450 nm: 380–450 nm carry the 450-nm values
    for wl in (380.0, 400.0, 445.0):
        assert data.pigment_k("C", wl) == pytest.approx(data.pigment_k("C", 450.0), abs=1e-12)
        assert data.pigment_n("C", wl) == pytest.approx(data.pigment_n("C", 450.0), abs=1e-12)
    # a squaraine absorbs the red (a cyan): k at 640 nm ≫ k in the blue
    assert data.pigment_k("C", 640.0) > 20 * data.pigment_k("C", 460.0)


def test_magenta_is_rhodamine_6g_with_its_measured_n():
    data = default_materials()
    for wl, (n, k) in R6G.items():
        assert data.pigment_n("M", wl) == pytest.approx(n, abs=2e-6)
        assert data.pigment_k("M", wl) == pytest.approx(k, abs=2e-6)
        assert data.pigment_k("R", wl) == pytest.approx(k, abs=2e-6)       # the same dye as R
        assert data.pigment_n("R", wl) == PIGMENT_REAL_INDEX               # R keeps the paper's 1.4


def test_black_is_amorphous_carbon_with_its_measured_n():
    data = default_materials()
    for wl in (415.0, 540.0):
        assert data.pigment_n("K", wl) == pytest.approx(_lerp(ARAKAWA, wl, 1), abs=1e-6)
        assert data.pigment_k("K", wl) == pytest.approx(_lerp(ARAKAWA, wl, 2), abs=1e-6)
    wl = np.arange(380.0, 781.0, 10.0)
    n, k = data.pigment_n("K", wl), data.pigment_k("K", wl)
    assert np.all((n > 1.9) & (n < 2.5)) and np.all((k > 0.65) & (k < 0.95))   # broadband, n ≈ 2
    np.testing.assert_allclose(pigment_eps("K", wl), (n + 1j * k) ** 2)


def test_the_database_reader_reads_the_tabulated_block(tmp_path):
    path = tmp_path / "x.yml"
    path.write_text("REFERENCES: |\n    someone\nDATA:\n  - type: tabulated nk\n    data: |\n"
                    "        0.5000 2.0 0.5\n        0.4000 1.5 0.25\nSPECS:\n    x: 1\n")
    wl, n, k = read_database_nk(path)
    np.testing.assert_allclose(wl, [400.0, 500.0])
    np.testing.assert_allclose(n, [1.5, 2.0])
    np.testing.assert_allclose(k, [0.25, 0.5])
    assert GRID_NM[0] == 360.0 and GRID_NM[-1] == 830.0


def test_new_letters_parse_and_mix():
    ink = parse_ink("K8+C4.5+M1.5")
    assert ink.label == "K8+C4.5+M1.5" and ink.total_fraction == pytest.approx(0.14)
    assert {p.name for p in PIGMENTS.values()} >= {"red", "yellow", "blue", "green", "cyan", "magenta", "black"}
    wl = np.array([450.0, 650.0])
    data = default_materials()
    expected = 0.86 * 1.558**2 + sum(f * (data.pigment_n(c, wl) + 1j * data.pigment_k(c, wl)) ** 2
                                     for c, f in (("K", 0.08), ("C", 0.045), ("M", 0.015)))
    np.testing.assert_allclose(molecular_eps(ink, wl), expected)


def test_the_papers_pigments_are_unchanged_by_the_process_pigments():
    """R, Y, B keep Re η = 1.4 and their k; their films are bit-identical with data that hold
    only R, Y, B (what the package held before the process pigments)."""
    data = default_materials()
    only_paper = dataclasses.replace(data, k={c: data.k[c] for c in "RYB"}, n={})
    wl = GRID_NM
    sigma = np.linspace(0.0, np.pi / 2, 7)
    for spec in ("R30", "Y30", "B30", "G30", "Y7.5+B7.5"):
        ink = parse_ink(spec)
        np.testing.assert_array_equal(molecular_eps(ink, wl, data), molecular_eps(ink, wl, only_paper))
        a = build_thinfilm_table(ink, 1000.0, wl, sigma, data)
        b = build_thinfilm_table(ink, 1000.0, wl, sigma, only_paper)
        np.testing.assert_array_equal(a.R_spec, b.R_spec)
        np.testing.assert_array_equal(a.T_coh, b.T_coh)
    for code in "RYB":
        np.testing.assert_array_equal(data.pigment_n(code, wl), 1.4)


def test_an_edited_n_gives_a_new_cache_key(tmp_path):
    from importlib import resources

    text = resources.files("solver.data").joinpath("pigments_nk.csv").read_text().splitlines()
    header = next(i for i, ln in enumerate(text) if ln.startswith("wavelength_nm"))
    col = text[header].split(",").index("n_black")
    row = next(i for i, ln in enumerate(text) if ln.startswith("550.0,"))
    cells = text[row].split(",")
    cells[col] = f"{float(cells[col]) * 1.01:.6f}"
    text[row] = ",".join(cells)
    path = tmp_path / "edited.csv"
    path.write_text("\n".join(text) + "\n")
    edited = load_material_data(path)
    assert edited.fingerprint != default_materials().fingerprint
    assert table_request("K10", materials=edited).key() != table_request("K10").key()
    # the local field follows the measured n
    lf = default_materials().with_local_field()
    eps_k = (default_materials().pigment_n("K", 550.0) + 1j * default_materials().pigment_k("K", 550.0)) ** 2
    h = 1.558**2
    assert lf.pigment_eps("K", 550.0) == pytest.approx(h + 3 * h * (eps_k - h) / (eps_k + 2 * h))


def test_a_spectra_file_with_an_unknown_column_is_refused(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("wavelength_nm,k_red,k_yellow,k_blue,k_purple\n400,0,0,0,0\n500,0,0,0,0\n")
    with pytest.raises(ValueError, match="unknown column 'k_purple'"):
        load_material_data(path)


def test_the_derivation_writes_a_file_the_package_reads(tmp_path, capsys):
    """derive_pigments on a miniature raw folder and database: every column where the package
    looks for it, biaxial axes averaged, values held beyond a file's range."""
    from solver.data import derive_pigments as D

    raw, db = tmp_path / "raw", tmp_path / "db"
    raw.mkdir()
    for parts in D.K_SOURCES.values():
        for name, _ in parts:
            (raw / name).write_text("# test\nwavelength_nm,n,k\n300,1.5,0.2\n900,1.5,0.4\n")
    for colour, parts in D.NK_SOURCES.items():
        for i, (path, _) in enumerate(parts):
            f = db / path
            f.parent.mkdir(parents=True, exist_ok=True)
            start = 0.45 if colour == "cyan" else 0.30
            f.write_text(f"DATA:\n  - type: tabulated nk\n    data: |\n        {start} {1.0 + i} {0.1 * (i + 1)}\n"
                         f"        0.9 {1.0 + i} {0.1 * (i + 1)}\n")
    assert D.main(["derive_pigments", str(raw), str(db)]) == 0
    out = tmp_path / "pigments.csv"
    out.write_text(capsys.readouterr().out)
    data = load_material_data(out)
    np.testing.assert_allclose(data.pigment_k("R", 600.0), 0.3)              # (0.2 + 0.4)/2 at 600 nm
    np.testing.assert_allclose(data.pigment_n("C", [380.0, 700.0]), 2.0)     # mean of 1, 2, 3; held below 450
    np.testing.assert_allclose(data.pigment_k("C", 380.0), 0.2)
    np.testing.assert_allclose(data.pigment_n("K", 500.0), 1.0)
    assert data.pigment_n("Y", 500.0) == PIGMENT_REAL_INDEX
