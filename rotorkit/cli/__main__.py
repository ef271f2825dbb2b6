"""``python -m rotorkit.cli``: the same as the ``rotorkit`` command."""

import sys

from . import main

sys.exit(main())
