"""Applications of the `ink` BSDF: printing an image (`python -m inkbsdf.print`), rendering a
scene (`python -m inkbsdf.render`), the page scenes they write, image files, the demo's tables.

The plugin itself (the BSDF, its tables, the variants) is the package above this one and imports
nothing from here."""
