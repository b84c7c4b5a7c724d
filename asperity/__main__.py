"""``python -m asperity`` is the same as the ``asperity`` command."""

from asperity.pipelines.cli import main

main()  # ends the process with the command's exit status
