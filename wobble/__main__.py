"""``python -m wobble`` runs the command line."""

import sys

from wobble.cli import console

sys.exit(console())
