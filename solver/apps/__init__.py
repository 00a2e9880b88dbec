"""Applications of the physics: the `ink-tables` command (`cli`), the paper's figures and
findings (`figures`), and printing an image — separation and halftones (`separation`).

The physics (materials and inks, geometry, the wave solver, thin films, tables, colour
measurement, the print model) lives in the packages beside this one and imports nothing from
here."""
