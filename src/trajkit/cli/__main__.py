"""``python -m trajkit.cli``: the command-line tool, as the ``trajkit`` script runs it."""

import sys

from trajkit.cli import main

sys.exit(main())
