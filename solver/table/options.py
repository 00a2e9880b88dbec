"""The options of a table request: one list, from which the CLI's options, the scene parameters
of an in-scene ink and the messages of validation are all derived.

Each `RequestOption` names a keyword of `request.table_request` (its `name`), the CLI option that
sets it (`cli`), the scene parameter (`scene`, None where scenes leave it to the CLI: grids
and the cell are the CLI's) and the Python type a scene gives it. Adding an option here adds it everywhere (the
CLI parses each by its name: solver/apps/cli/build.py; a test checks that every option has its
CLI argument and its place in `TableRequest.to_options`), and a table's request round-trips
through its file (`TableRequest.from_meta`).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class RequestOption:
    name: str                         # keyword of table_request
    cli: str                          # the ink-tables option
    scene: str | None = None          # the ink BSDF's parameter (None: CLI only)
    scene_type: type | None = None    # the Python type of the scene value (None: as given)
    wave: bool = False                # a field of WaveSettings (particle inks only)

    @property
    def dest(self) -> str:
        """The argparse destination of the CLI option."""
        return self.cli.removeprefix("--").replace("-", "_")


OPTIONS = (
    RequestOption("ink", "--ink", "ink", str),
    RequestOption("particles", "--particles", "particles", str),
    RequestOption("thickness_nm", "--thickness", "thickness", None),
    RequestOption("wavelengths_nm", "--wavelengths"),
    RequestOption("sigma_rad", "--angles"),
    RequestOption("dphi_count", "--dphi-count"),
    RequestOption("polarisation", "--polarisation", "polarisation", str),
    RequestOption("local_field", "--local-field", "local_field", bool),
    RequestOption("accuracy", "--accuracy", "accuracy", str),
    RequestOption("realizations", "--realizations", "realizations", int, wave=True),
    RequestOption("target_se", "--target-se", "target_se", float, wave=True),
    RequestOption("max_realizations", "--max-realizations", "max_realizations", int, wave=True),
    RequestOption("azimuths", "--azimuths", "azimuths", int, wave=True),
    RequestOption("tolerance", "--tolerance", "tolerance", float, wave=True),
    RequestOption("tier", "--tier", "tier", str, wave=True),
    RequestOption("cell_nm", "--cell", wave=True),
    RequestOption("grid", "--grid", wave=True),
    RequestOption("solver_tol", "--solver-tol", "solver_tol", float, wave=True),
    RequestOption("seed", "--seed", "seed", int, wave=True),
    RequestOption("wavelength_stride", "--wavelength-stride", "wavelength_stride", int, wave=True),
)
BY_NAME = {o.name: o for o in OPTIONS}
#: the CLI name of each option, for messages (validation says which option is wrong)
OPTION = {o.name: o.cli for o in OPTIONS}
#: scene parameter → table_request keyword, for an in-scene ink
SCENE_PARAMS = {o.scene: o.name for o in OPTIONS if o.scene}
#: the wave settings a request takes (table_request's **wave_overrides)
WAVE_OPTIONS = tuple(o.name for o in OPTIONS if o.wave)
