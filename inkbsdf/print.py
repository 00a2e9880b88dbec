"""`python -m inkbsdf.print IMAGE …`: print an image (the application lives in inkbsdf/apps/print.py)."""

import sys

from inkbsdf.apps.print import main

if __name__ == "__main__":
    sys.exit(main())
