"""`python -m inkbsdf.render SCENE …`: render a scene (the application lives in inkbsdf/apps/render.py)."""

import sys

from inkbsdf.apps.render import run

if __name__ == "__main__":
    sys.exit(run())
