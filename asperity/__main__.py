"""``python -m asperity`` is the same as the ``asperity`` command."""

import sys

from asperity.pipelines.cli import main
from asperity.pipelines.engine.interrupts import forget_escaped_interrupts

status = main()
forget_escaped_interrupts()  # else a Ctrl-C seen inside a library's exec ends as -SIGINT, not 130
sys.exit(status)
