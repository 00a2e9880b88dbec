"""A press characterisation data set of the print model: an IT8.7/4-style chart of coverage
mixes and their predicted CIELAB, in CGATS.17 text, the format ICC profilers read (docs/printing.md,
"Characterisation").

    text = characterisation_text(model, inks, black=3)
    Path("press.txt").write_text(text)

The chart (`chart`): with four inks of which one is black, CMYK patches in the spirit of
IT8.7/4 (ISO 12642-2): the CMY cube at nine levels with no black, CMY at five levels over
black at 20, 40, 60, 80 %, the black ramp in 5 % steps and each chromatic ink's ramp in
2.5 % steps — 1,341 distinct patches, coverages in percent. Other ink sets get the full
factorial of their inks at `GENERIC_LEVELS` (CGATS nCLR fields). Patches over the total area
coverage limit are kept (a profiler reads the limit from its own settings).

The colour of a patch is the model's (`PrintColourModel`: its coverage model, paper and
measurement, 45:0 D50 2° by default) as absolute CIELAB and XYZ (the perfect diffuser = 100),
the way an instrument reports a press sheet; the header says it is a prediction.

Which chromatic ink is C, M and Y: the ink whose main pigment is C, M or Y; otherwise the
assignment of the three chromatic inks to the hues 235°, 350° and 95° (cyan, magenta, yellow
solids of ISO 12647-2) that minimises the sum of hue differences of their solids.
"""

from __future__ import annotations

import datetime
from itertools import permutations, product

import numpy as np

CMY_LEVELS = (0, 10, 20, 30, 40, 55, 70, 85, 100)
OVER_BLACK_LEVELS = (0, 20, 40, 70, 100)
BLACK_STEPS = (20, 40, 60, 80)
RAMP_STEP = 2.5
BLACK_RAMP_STEP = 5.0
GENERIC_LEVELS = (0, 10, 20, 30, 40, 55, 70, 85, 100)
PROCESS_HUES_DEG = {"C": 235.0, "M": 350.0, "Y": 95.0}


def cmyk_chart() -> np.ndarray:
    """Distinct CMYK patches in percent [N, 4] (module docstring), paper white first."""
    rows = [(c, m, y, 0.0) for c, m, y in product(CMY_LEVELS, repeat=3)]
    rows += [(c, m, y, float(k)) for k in BLACK_STEPS for c, m, y in product(OVER_BLACK_LEVELS, repeat=3)]
    rows += [(0.0, 0.0, 0.0, float(k)) for k in np.arange(0.0, 100.0 + 1e-9, BLACK_RAMP_STEP)]
    for i in range(3):
        for v in np.arange(0.0, 100.0 + 1e-9, RAMP_STEP):
            r = [0.0, 0.0, 0.0, 0.0]
            r[i] = float(v)
            rows.append(tuple(r))
    chart = np.array(rows, dtype=np.float64)
    _, first = np.unique(chart, axis=0, return_index=True)
    return chart[np.sort(first)]


def generic_chart(n_inks: int) -> np.ndarray:
    return np.array(list(product(GENERIC_LEVELS, repeat=n_inks)), dtype=np.float64)


def process_order(model, inks, black: int) -> list[int]:
    """Indices of the inks playing C, M, Y, K (module docstring)."""
    from .printset import dominant_pigment

    chromatic = [i for i in range(len(inks)) if i != black]
    letters = {}
    for i in chromatic:
        main = dominant_pigment(inks[i])
        if main in PROCESS_HUES_DEG:
            letters[main] = i
    if len(letters) == 3:
        return [letters["C"], letters["M"], letters["Y"], black]
    lab = model.lab(np.eye(model.n_inks))
    hue = np.degrees(np.arctan2(lab[:, 2], lab[:, 1])) % 360.0
    aims = [PROCESS_HUES_DEG[x] for x in "CMY"]
    dist = lambda perm: sum(abs((hue[i] - a + 180.0) % 360.0 - 180.0) for i, a in zip(perm, aims))  # noqa: E731
    return list(min(permutations(chromatic), key=dist)) + [black]


def characterisation_text(model, inks, black: int | None, created: str | None = None) -> str:
    """CGATS.17 text of the chart and the model's absolute CIELAB and XYZ (module docstring)."""
    inks = tuple(inks)
    if black is not None and len(inks) == 4:
        order = process_order(model, inks, black)
        chart = cmyk_chart()
        fields = ["CMYK_C", "CMYK_M", "CMYK_Y", "CMYK_K"]
        roles = ", ".join(f"{f[-1]} = {inks[i]}" for f, i in zip(fields, order))
    else:
        order = list(range(len(inks)))
        chart = generic_chart(len(inks))
        fields = [f"{len(inks)}CLR_{i + 1}" for i in range(len(inks))]
        roles = ", ".join(f"{f} = {ink}" for f, ink in zip(fields, inks))
    coverages = np.zeros((chart.shape[0], len(inks)))
    coverages[:, order] = chart / 100.0
    xyz = model.xyz(coverages)
    lab = model.absolute_lab(coverages)
    xyz100 = 100.0 * xyz / model.absolute_white_xyz[1]
    m = model.measurement
    created = created or datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    geometry = {"45:0": "45/0"}.get(m.geometry.name, m.geometry.name)
    lines = [
        "CGATS.17",
        'ORIGINATOR\t"inkbsdf (python -m inkbsdf.print --characterisation)"',
        f'DESCRIPTOR\t"IT8.7/4-style chart predicted by the inkbsdf print model: {roles}; '
        f'{model.coverage_model}; paper albedo {float(np.mean(model.predictor.paper)):g}; not a measurement"',
        f'CREATED\t"{created}"',
        'INSTRUMENTATION\t"none: colours predicted by the print model"',
        f'MEASUREMENT_SOURCE\t"Illumination={m.illuminant}\tObserverAngle={m.observer}\tWhiteBase=Abs\tFilter=No"',
        'KEYWORD\t"MEASUREMENT_GEOMETRY"',
        f'MEASUREMENT_GEOMETRY\t"{geometry}"',
        f"NUMBER_OF_FIELDS\t{len(fields) + 7}",
        "BEGIN_DATA_FORMAT",
        "\t".join(["SAMPLE_ID", *fields, "XYZ_X", "XYZ_Y", "XYZ_Z", "LAB_L", "LAB_A", "LAB_B"]),
        "END_DATA_FORMAT",
        f"NUMBER_OF_SETS\t{chart.shape[0]}",
        "BEGIN_DATA",
    ]
    for n, (row, x, l) in enumerate(zip(chart, xyz100, lab), start=1):
        lines.append("\t".join([str(n), *(f"{v:.2f}" for v in row), *(f"{v:.4f}" for v in x),
                                *(f"{v:.4f}" for v in l)]))
    lines.append("END_DATA")
    return "\n".join(lines) + "\n"
