"""``python -m wobble`` runs the command line."""

import sys

from wobble.cli import main

sys.exit(main())
