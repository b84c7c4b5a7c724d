"""The error types and exit statuses shared by every asperity package and command.

Exit statuses of every ``asperity`` command, one meaning each:

====  =================  ==============================================================
code  name               meaning
====  =================  ==============================================================
0     OK                 success: every number shown is one the report stands behind
1     NOT_CONVERGED      a solver did not converge; everything is still written and the
                         report says which solve failed
2     BAD_INPUT          bad input: a file, a configuration key, an option or a value
                         (the message names it, what was expected and what was found)
3     INVALID_RESULT     computed, but outside the model's validity (the report's verdict
                         says why); the numbers are written, marked invalid
70    INTERNAL_ERROR     a defect in asperity itself (not your input): please report it
130   INTERRUPTED        interrupted (Ctrl-C); finished stages are kept
====  =================  ==============================================================
"""

from __future__ import annotations

from enum import IntEnum


class ExitStatus(IntEnum):
    """Process exit statuses of the ``asperity`` commands (see the module docstring)."""

    OK = 0
    NOT_CONVERGED = 1
    BAD_INPUT = 2
    INVALID_RESULT = 3
    INTERNAL_ERROR = 70
    INTERRUPTED = 130


class InputError(ValueError):
    """Bad input named by the user: a file, a configuration key, an option or an argument.

    Every validation error of the library derives from this class, so that the command line
    reports it as bad input (exit status 2) and anything else as an internal error (70).
    The message names the file, key or argument, what was expected and what was found.
    """
