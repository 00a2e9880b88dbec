"""inkbsdf solver: ink materials, layer geometry, the wave solver and the tables the BSDF reads.

Lengths in nm, angles in radians (degrees only at the CLI), concentrations as fractions
(percent only at the CLI).  See docs/design.md for the physics.
"""

__version__ = "0.1.0"
