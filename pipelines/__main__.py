"""``python -m asperity.pipelines`` is the same as the ``asperity`` command."""

import sys

from asperity.pipelines.cli import main

sys.exit(main())
