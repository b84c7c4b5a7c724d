"""The ``asperity`` command line: a thin shell over the package's functions.

Each package contributes its own sub-commands through a ``register(subparsers)`` function in its
``cli`` module; this module assembles them, runs the chosen handler and turns what comes out of
it into one line on stderr and an exit status (:class:`asperity.errors.ExitStatus`).

Exit statuses: :class:`asperity.errors.ExitStatus`, one meaning each (its members carry them;
``asperity --help`` lists the labels). Status 2 (``BAD_INPUT``) is a usage error (unknown option,
missing argument: argparse's message), an :class:`asperity.errors.InputError` (a bad file,
configuration key, option or value: the message names it), or a file-system error on a path the
user named (not found, a directory, no permission, exists) or of the user's storage (read-only,
full disk, quota, I/O error); status 70 (``INTERNAL_ERROR``) any other exception: a defect in
asperity, not in the input.

What reaches stderr: ``asperity CMD: error: MESSAGE`` (status 2); ``asperity CMD: internal
error: TYPE: MESSAGE (please report this; ...)`` (status 70), with the traceback above it when the
environment variable ``ASPERITY_DEBUG`` is set to anything but ``0`` or empty (for any error);
``asperity CMD: interrupted`` (status 130; a Ctrl-C stops the run at its next safe point,
:mod:`asperity.pipelines.engine.interrupts`). A reader that closes the output pipe early
(``asperity scan FILE | head -1``) ends nothing: the command goes on quietly to its own end and
status, its further output dropped (:class:`ClosedPipeTolerant`). Error and warning lines are
at most :data:`MAX_LINE` (1000) characters, each echoed value cut to its ends with its full
length said, control characters shown escaped (:func:`asperity.errors.error_line`: an escape
sequence in a file name or TOML key never reaches the terminal raw). Python warnings raised
while a command runs (e.g.
:class:`asperity.statmodel.TaborWarning`, numpy's RuntimeWarnings) are printed as one line each,
``asperity CMD: warning: MESSAGE``, once per distinct message; the usual warning filters
(``python -W``, ``PYTHONWARNINGS``) still decide which are shown.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import importlib
import os
import sys
import traceback
import warnings
from collections.abc import Iterator, Sequence
from typing import Any

from asperity.atomic import storage_errno
from asperity.errors import MAX_ERROR_LINE, ExitStatus, InputError, error_line, exit_status_epilog
from asperity.pipelines import __version__
from asperity.pipelines.engine.interrupts import InterruptGuard
from asperity.quantities import OneLineErrorParser

#: Modules that provide ``register(subparsers)``; each adds its sub-commands.
COMMAND_MODULES: tuple[str, ...] = (
    "asperity.topo.cli",  # stats, scan, synth
    "asperity.bem.cli",  # bem
    "asperity.statmodel.cli",  # friction, figures
    "asperity.pipelines.cli.run",  # run
    "asperity.pipelines.cli.init",  # init
)

#: File-system errors that concern a path the user named: reported as bad input (status 2).
PATH_ERRORS: tuple[type[OSError], ...] = (
    FileNotFoundError,
    FileExistsError,
    IsADirectoryError,
    NotADirectoryError,
    PermissionError,
)

#: Longest error or warning line, characters (quoted input is cut shorter where quoted).
MAX_LINE = MAX_ERROR_LINE

#: Environment variable that adds the traceback to an error line.
DEBUG_VARIABLE = "ASPERITY_DEBUG"


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every package's sub-commands."""
    parser = OneLineErrorParser(
        prog="asperity",
        description="Adhesive friction of rough elastic contacts (SI units throughout).",
        epilog=exit_status_epilog(),
    )
    parser.add_argument("--version", action="version", version=f"asperity {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        module = importlib.import_module(name)
        module.register(subparsers)
    return parser


def _debugging() -> bool:
    return os.environ.get(DEBUG_VARIABLE, "") not in ("", "0")


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _warning_text(message: Warning | str, category: type[Warning]) -> str:
    """The warning's message; foreign categories (numpy's RuntimeWarning, ...) are named."""
    text = _one_line(message)
    return text if _own_category(category) else f"{category.__name__}: {text}"


def _own_category(category: type[Warning]) -> bool:
    """asperity's warnings and plain UserWarnings (not numpy's RuntimeWarning, ...)."""
    return category.__module__.startswith("asperity") or category is UserWarning


@contextlib.contextmanager
def warnings_as_lines(command: str, stream=None) -> Iterator[list[str]]:  # noqa: ANN001
    """Print each warning raised inside the block as ``asperity COMMAND: warning: ...``.

    One line per distinct message, on ``stream`` (default: ``sys.stderr`` at the time of the
    warning); the active warning filters still decide which warnings are shown. asperity's own
    warnings (and UserWarning) are printed at once; foreign ones (numpy's RuntimeWarning, ...)
    wait until the next own warning or the end of the block, and are dropped when the block
    ends by an exception: a command that fails prints its one error line, not the numerical
    noise of the computation it abandoned (``ASPERITY_DEBUG=1`` prints them).
    """
    shown: set[str] = set()
    waiting: list[str] = []

    def emit(text: str) -> None:
        print(error_line(f"asperity {command}: warning: ", text), file=stream or sys.stderr)

    def show(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
        text = _warning_text(message, category)
        if text in shown:
            return
        shown.add(text)
        if not _own_category(category):
            waiting.append(text)
            return
        while waiting:
            emit(waiting.pop(0))
        emit(text)

    with warnings.catch_warnings():
        warnings.showwarning = show
        try:
            yield waiting
        except BaseException:
            if not _debugging():
                waiting.clear()
            raise
        finally:
            while waiting:
                emit(waiting.pop(0))


def _path_error_text(exc: BaseException) -> str:
    """``"<file>: <reason>"`` for an OSError naming its file, else the exception's text (h5py's
    RuntimeError of a full disk has neither attribute)."""
    filename, reason = getattr(exc, "filename", None), getattr(exc, "strerror", None)
    if filename is not None and reason:
        return f"{filename}: {reason}"
    return str(exc)


#: Storage errors that are the user's disk whatever raised them (full, quota, read-only).
DISK_ERRNOS = frozenset((errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS))


def _storage_failure(exc: BaseException) -> bool:
    """A full, read-only or over-quota disk; an I/O or access error only with the path it
    concerns (a bare ``OSError(EIO)`` may be a defect and stays an internal error)."""
    code = storage_errno(exc)
    return code in DISK_ERRNOS or (code is not None and bool(getattr(exc, "filename", None)))


def _report_exception(command: str, exc: BaseException) -> ExitStatus:
    """Print the one-line report of ``exc`` (and its traceback when debugging); its status.

    The line is bounded and inert (:func:`asperity.errors.error_line`): at most
    :data:`MAX_LINE` characters, echoed values cut, control characters escaped.
    """
    if _debugging():
        traceback.print_exception(exc, file=sys.stderr)
    if isinstance(exc, InputError):
        print(error_line(f"asperity {command}: error: ", str(exc)), file=sys.stderr)
        return ExitStatus.BAD_INPUT
    if isinstance(exc, PATH_ERRORS) or _storage_failure(exc) or _name_too_long(exc):
        print(error_line(f"asperity {command}: error: ", _path_error_text(exc)), file=sys.stderr)
        return ExitStatus.BAD_INPUT
    print(
        error_line(
            f"asperity {command}: internal error: {type(exc).__name__}: ",
            _one_line(exc),
            f" (please report this; run with {DEBUG_VARIABLE}=1 for the traceback)",
        ),
        file=sys.stderr,
    )
    return ExitStatus.INTERNAL_ERROR


def _name_too_long(exc: BaseException) -> bool:
    """A path the user named that the file system refuses as too long (ENAMETOOLONG)."""
    return isinstance(exc, OSError) and exc.errno == errno.ENAMETOOLONG


def _status(value: int | None) -> ExitStatus:
    """A handler's return value as an exit status (None means success; an undocumented code
    raises ValueError, reported as an internal error)."""
    return ExitStatus.OK if value is None else ExitStatus.from_code(int(value))


class ClosedPipeTolerant:
    """A text stream whose reader may leave: a closed pipe drops the rest of the output.

    ``asperity scan FILE | head -1``: once ``head`` has exited, the next write raises
    BrokenPipeError. The command then goes on to its end (its files written, its exit status
    as it chose) with the stream sent to the null device, quietly, instead of ending with a
    traceback or an internal error.
    """

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        """Write ``text``; drop it (and everything after) if the reader has gone."""
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            self._to_null()
            return len(text)

    def flush(self) -> None:
        """Flush; a reader that has gone is not an error."""
        try:
            self._stream.flush()
        except BrokenPipeError:
            self._to_null()
            self._stream.flush()

    def _to_null(self) -> None:
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, self._stream.fileno())
        finally:
            os.close(null)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``asperity`` command; returns the process exit status (module docstring).

    Called without ``argv`` (the ``asperity`` command and ``python -m asperity``), it ends the
    process itself once the status is known: the output is flushed and the process exits at
    once (:func:`os._exit`), skipping the interpreter's teardown, during which CPython restores
    the default SIGINT action: a Ctrl-C landing there killed the process by SIGINT
    (returncode -2) after it had printed its "outputs:" line. Every file is written and closed
    by then (atomic writes, locks released, executors shut down).
    """
    status = _command(argv)
    if argv is None:
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(OSError, ValueError):
                stream.flush()
        os._exit(int(status))
    return status


def _escape_unencodable(*streams: object) -> None:
    """A character a stream's encoding lacks (``±``, ``µ`` on an ASCII terminal) written as its
    escape (``\\xb1``), never an error that ends the run."""
    for stream in streams:
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            with contextlib.suppress(OSError, ValueError, TypeError):
                reconfigure(errors="backslashreplace")


def _command(argv: Sequence[str] | None) -> int:
    """The body of :func:`main`: parse, run the handler, turn the outcome into a status."""
    # Ctrl-C stops the run at its next safe point (pipelines.engine.interrupts); for the
    # command itself (argv None) one while the interpreter shuts down still ends with 130.
    interrupts = InterruptGuard(final=argv is None)
    if argv is None:  # the command itself: a reader that closes the pipe ends nothing
        _escape_unencodable(sys.stdout, sys.stderr)
        sys.stdout, sys.stderr = ClosedPipeTolerant(sys.stdout), ClosedPipeTolerant(sys.stderr)
    command = "?"
    try:
        with interrupts:
            args = _parse(argv)
            if isinstance(args, ExitStatus):
                return args
            command = args.command
            with warnings_as_lines(command):
                return _status(args.func(args))
    except KeyboardInterrupt:
        interrupts.close()
        return _interrupted(command)
    except Exception as exc:  # noqa: BLE001 (every exception gets a status of its own)
        interrupts.close()
        if interrupts.requested:  # a library turned the KeyboardInterrupt into another error
            return _interrupted(command)
        return _report_exception(command, exc)


def _parse(argv: Sequence[str] | None) -> argparse.Namespace | ExitStatus:
    """The parsed command line, or the status of a usage error (its line already printed)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:  # --help and --version exit 0 here; an option error is 2,
        if stop.code != ExitStatus.BAD_INPUT:  # its one line already printed
            raise
        return ExitStatus.BAD_INPUT
    if getattr(args, "func", None) is None:
        parser.print_help()
        return ExitStatus.BAD_INPUT
    return args


def _interrupted(command: str) -> ExitStatus:
    print(f"asperity {command}: interrupted; finished stages are kept", file=sys.stderr)
    return ExitStatus.INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
