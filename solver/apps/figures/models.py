"""The two models a figure can be drawn with (`ink-tables paper … --model`), each a choice of
tables and of the colour that is measured from them (docs/figures.md, "Two models").

    paper     the model exactly as the paper publishes it: TE (s) light only, the pigments' bulk
              ε, and the colour of its Fig. 6 strip — eq. (4) with the layer's diffuse light,
              no coherent mirror beam (measurement geometry `paper`); its strips are drawn
              without the mirror too.
    default   this project's model: unpolarised light (the mean of TE and TM faces), the
              pigments' local field, every order kept; colour measured as printers measure it
              (45:0, ISO 13655); its strips show the layer's mirror of a uniform surround.

Both measure under D50 and the 2° observer unless told otherwise, so that the difference
between the models is a difference of physics, not of illuminant.
"""

from __future__ import annotations

from dataclasses import dataclass

from solver.colour.measurement import DEFAULT_ILLUMINANT, DEFAULT_OBSERVER, Measurement, parse_measurement


@dataclass(frozen=True)
class Model:
    name: str
    polarisation: str            # of every table (table_request's)
    local_field: bool            # the pigments' local field
    measurement: Measurement     # the colour written to the CSV and tested by the findings
    mirror_in_strip: bool        # whether the Fig. 6 strip shows the layer's coherent mirror
    description: str

    def request_options(self) -> dict:
        return {"polarisation": self.polarisation, "local_field": self.local_field}


MODELS = {m.name: m for m in (
    Model("default", "unpolarised", True, parse_measurement("45:0", DEFAULT_ILLUMINANT, DEFAULT_OBSERVER), True,
          "unpolarised light, the pigments' local field, coherent orders kept"),
    Model("paper", "te", False, parse_measurement("paper", DEFAULT_ILLUMINANT, DEFAULT_OBSERVER), False,
          "the paper's model: TE light, bulk pigment ε, the layer's diffuse light (no coherent mirror)"),
)}
DEFAULT_MODEL = "default"


def parse_model(name: str) -> Model:
    if name not in MODELS:
        raise ValueError(f"--model {name!r}: choose one of {', '.join(MODELS)}")
    return MODELS[name]
