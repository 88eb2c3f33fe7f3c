"""``python -m celtstone`` runs the command-line interface."""

import sys

from celtstone.cli.main import main

sys.exit(main())
