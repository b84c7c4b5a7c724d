"""``python -m pipelines`` is the same as the ``asperity`` command."""

import sys

from pipelines.cli import main

sys.exit(main())
