"""The output directory of a job: one run at a time, clean failures, no stale temporary files.

Three guarantees of ``asperity run --out DIR`` (and :func:`pipelines.job.run_job`):

* **One run per directory.** :class:`OutputLock` holds an exclusive lock on ``DIR/.asperity.lock``
  for the whole run (stages, figures, report). A second run on the same directory stops at once
  with :class:`OutputLockedError` (exit status 2) naming the lock file and the holder's pid,
  host and start time. On POSIX the lock is ``fcntl.flock`` on that file: the kernel releases it
  when the holding process ends in any way (``kill -9`` included), so a lock is never left
  behind by a dead run on this host; the pid record is then taken over and the log says so. On
  Windows it is ``msvcrt.locking`` on one byte of the file, released by the system the same way.
  A lock held from another host over a network file system cannot be checked from here: the
  message says to delete the file only when that run is gone.
* **Clean failures.** A directory that cannot be created or written (read-only, not a
  directory, no permission) is :class:`OutputDirError`, and a full disk or quota while
  writing is :class:`OutputWriteError`: one line, exit status 2 (a file-system error on a
  path the user named), the previous ``results.h5`` untouched.
* **No stale temporary files.** Every output file is written through a temporary
  ``.NAME.<pid>.tmp`` beside it (:mod:`asperity.atomic`); :func:`remove_stale_temporaries`
  (called under the lock) removes those of processes
  that no longer run on this host, and reports each one removed.

Where the file system refuses ``flock`` (some network or FUSE file systems), the pid record
alone decides, as best it can: a record of a live pid on this host, or of any other host,
refuses the run; a record of a dead pid on this host is taken over.

Lock re-entry: the same process may take the lock of one directory again (the command line
holds it around the job and the report, the job takes it too); it is released when the
outermost holder lets go.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import errno
import json
import os
import re
import socket
import sys
import threading
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path
from types import TracebackType
from typing import BinaryIO, cast

from asperity.atomic import (  # noqa: F401 (re-exported: their documented home)
    STORAGE_ERRNOS,
    OutputWriteError,
    storage_errno,
    write_error,
)
from asperity.errors import InputError
from asperity.schema import clip

#: Name of the lock file in the output directory.
LOCK_NAME = ".asperity.lock"
#: Byte offset locked on Windows (past the pid record, so that the record stays readable).
_WINDOWS_LOCK_OFFSET = 1 << 20
_TEMPORARY = re.compile(r"^\.(?P<name>.+)\.(?P<pid>\d+)\.tmp$")  # asperity.atomic's


class OutputLockedError(InputError):
    """Another run holds the output directory's lock (exit status 2)."""


class OutputDirError(InputError):
    """The output directory cannot be created or written (exit status 2)."""


def pid_alive(pid: int) -> bool:
    """Whether a process with this id runs on this host (POSIX; on Windows: assume it does)."""
    if pid <= 0:
        return False
    if sys.platform == "win32":  # os.kill(pid, 0) would terminate it there
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, another user's
        return True
    return True


def remove_stale_temporaries(directory: Path, log: Callable[[str], None]) -> list[Path]:
    """Remove ``.NAME.<pid>.tmp`` files of processes that no longer run on this host.

    Call it while holding the directory's :class:`OutputLock` (no other run of asperity then
    writes there). Returns the files removed; ``log`` gets one line for each.
    """
    removed = []
    for path in sorted(directory.glob(".*.*.tmp")):
        match = _TEMPORARY.match(path.name)
        if match is None or int(match.group("pid")) == os.getpid():
            continue
        if sys.platform != "win32" and pid_alive(int(match.group("pid"))):
            continue  # (on Windows the lock alone says that no other run writes here)
        try:
            path.unlink()
        except FileNotFoundError:
            continue
        removed.append(path)
        log(f"removed {path}: temporary file of an interrupted run (pid {match.group('pid')})")
    return removed


def _lock_exclusive(handle: BinaryIO) -> bool:
    """Try to lock ``handle`` without waiting; False when another process holds it."""
    if sys.platform == "win32":
        import msvcrt

        handle.seek(_WINDOWS_LOCK_OFFSET)
        try:
            msvcrt.locking(handle.fileno(), msvcrt.LK_NBLCK, 1)
        except OSError:
            return False
        return True
    import fcntl

    try:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    except OSError as exc:
        if exc.errno in (errno.EAGAIN, errno.EACCES):
            return False
        raise
    return True


def _read_record(path: Path) -> dict:
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
        record = json.loads(text[: _WINDOWS_LOCK_OFFSET // 2].split("\n", 1)[0] or "{}")
    except (OSError, ValueError):
        return {}
    return record if isinstance(record, dict) else {}


class OutputLock:
    """Exclusive use of an output directory by this process (a context manager).

    Parameters
    ----------
    directory : path
        The output directory (created when missing).
    log : callable, optional
        Receives one line when a stale lock record or temporary file is taken over / removed.
    option : str
        How the user named the directory, first in every message (``--out``, ``OUT_DIR``).

    Raises
    ------
    OutputLockedError
        Another live process holds the lock.
    OutputDirError
        The directory cannot be created, or the lock file cannot be written there.
    """

    _held: dict[Path, tuple[OutputLock, int]] = {}
    _guard = threading.Lock()

    def __init__(
        self,
        directory: str | Path,
        log: Callable[[str], None] | None = None,
        option: str = "--out",
    ):
        self.directory = Path(directory)
        self.option = option
        self.path = self.directory / LOCK_NAME
        self.log = log or (lambda line: None)
        self._handle: BinaryIO | None = None
        self._key: Path | None = None

    def __enter__(self) -> OutputLock:
        self.acquire()
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.release()

    def acquire(self) -> None:
        """Take the lock (or re-enter it when this process holds it already)."""
        self._created_directory = not self.directory.exists()
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputDirError(
                f"{self.option} {self.directory}: cannot create the output directory "
                f"({exc.strerror or exc})"
            ) from exc
        key = self.directory.resolve()
        with OutputLock._guard:
            if key in OutputLock._held:
                owner, depth = OutputLock._held[key]
                OutputLock._held[key] = (owner, depth + 1)
                self._key = key
                return
            self._take()
            OutputLock._held[key] = (self, 1)
            self._key = key
        remove_stale_temporaries(self.directory, self.log)

    def _take(self) -> None:
        for _attempt in range(3):  # a lock file removed by its holder meanwhile: open it anew
            handle = self._open_lock_file()
            try:
                locked = _lock_exclusive(handle)
            except OSError:  # a file system without locks: fall back to the pid record alone
                locked = not self._record_is_live()
            if not locked or _same_file(handle, self.path):
                break
            handle.close()
        self._hold(handle, locked)

    def _open_lock_file(self) -> BinaryIO:
        try:
            return open(self.path, "a+b")  # noqa: SIM115 (held until release)
        except OSError as exc:
            raise OutputDirError(
                f"{self.option} {self.directory}: cannot write in the output directory "
                f"({exc.strerror or exc}: {self.path})"
            ) from exc

    def _hold(self, handle: BinaryIO, locked: bool) -> None:
        """Keep ``handle`` as this run's lock (or refuse: another run holds it)."""
        if not locked:
            holder = _read_record(self.path)
            handle.close()
            raise OutputLockedError(self._locked_message(holder))
        previous = _read_record(self.path)
        self._handle = handle
        try:
            self._write_record()
        except OSError as exc:  # a full disk or quota: name the lock file, hold nothing
            self._handle = None
            handle.close()
            raise OutputDirError(
                f"{self.option} {self.directory}: cannot write the lock file {self.path} "
                f"({exc.strerror or exc})"
            ) from exc
        if previous.get("pid") and previous.get("pid") != os.getpid():
            self.log(
                f"{self.path}: took over the lock of pid {previous.get('pid')} on "
                f"{previous.get('host', '?')} (that run ended without releasing it)"
            )

    def _record_is_live(self) -> bool:
        """Whether the pid record names a run that may still hold the directory (a run on
        another host cannot be checked from here, so it counts as live)."""
        record = _read_record(self.path)
        if not record:
            return False
        if record.get("host") != socket.gethostname():
            return True
        try:
            return pid_alive(int(record.get("pid", 0)))
        except (TypeError, ValueError):
            return False

    def _write_record(self) -> None:
        """Write this run's pid record into the held lock file (replacing the last)."""
        record = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "started": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "command": clip(" ".join(sys.argv)),
        }
        handle = cast(BinaryIO, self._handle)  # only called by _hold, once it is set
        handle.seek(0)
        handle.truncate()
        handle.write((json.dumps(record) + "\n").encode())
        handle.flush()

    def _locked_message(self, holder: dict) -> str:
        pid, host = holder.get("pid", "?"), holder.get("host", "?")
        return (
            f"{self.option} {self.directory}: in use by another asperity run (pid {pid} on host "
            f"{host}, started {holder.get('started', '?')}; lock file {self.path}). Wait for it to "
            "finish or choose another --out. A run that ended on this host releases the lock "
            "by itself (a dead pid is taken over); delete the lock file only if that run is "
            "gone and the directory is shared with another host"
        )

    def release(self) -> None:
        """Let go (the outermost holder in this process unlocks and closes the file)."""
        if self._key is None:
            return
        with OutputLock._guard:
            owner, depth = OutputLock._held[self._key]
            if depth > 1:
                OutputLock._held[self._key] = (owner, depth - 1)
            else:
                del OutputLock._held[self._key]
                owner._close()
            self._key = None

    def _close(self) -> None:
        if self._handle is not None:
            with contextlib.suppress(OSError):  # a cleared record: this run ended cleanly
                self._handle.truncate(0)
            self._remove_if_nothing_written()
            self._handle.close()  # closing the file releases flock / msvcrt locks
            self._handle = None

    def _remove_if_nothing_written(self) -> None:
        """A run that wrote nothing leaves nothing: the lock file goes (still locked, so a
        run that opened it meanwhile sees it gone and opens a new one), and so does the
        directory when this run created it."""
        try:
            if [p.name for p in self.directory.iterdir()] != [LOCK_NAME]:
                return
            self.path.unlink()
        except OSError:
            return
        if getattr(self, "_created_directory", False):
            with contextlib.suppress(OSError):
                self.directory.rmdir()


def _same_file(handle: BinaryIO, path: Path) -> bool:
    """Whether ``path`` still names the file ``handle`` has open (not removed, not replaced)."""
    try:
        return os.path.samestat(os.fstat(handle.fileno()), os.stat(path))
    except OSError:
        return False


class DifferentJobError(InputError):
    """The output folder holds a finished run of a different job (exit status 2)."""


#: The stage whose presence makes a folder's run finished.
FINISHED_STAGE = "verdict"


def job_values(documents: Iterable[str]) -> dict[str, object]:
    """The configuration values the stage keys hash, by key path (``loading.normal_loads``),
    gathered from the stages' JSON key documents; asperity's version is left out, so the
    same job run by another version is the same job."""
    values: dict[str, object] = {}
    for text in documents:
        try:
            document = json.loads(text) if text else None
        except ValueError:
            continue
        config = document.get("config") if isinstance(document, dict) else None
        if isinstance(config, dict):
            values.update(config)
    return values


def refuse_a_different_finished_job(
    directory: Path,
    stored: Mapping[str, object],
    planned: Mapping[str, str],
    sources: tuple[str, str],
) -> None:
    """Refuse to overwrite a finished run of another job in ``directory``.

    Parameters
    ----------
    directory : Path
        The output folder.
    stored : mapping
        Its finished stages (:meth:`ResultStore.stored`: objects with ``key_inputs``).
    planned : mapping
        The new job's key documents (JSON) by stage.
    sources : (str, str)
        The stored job's and the new job's configuration sources, named in the message.

    Raises
    ------
    DifferentJobError
        The folder's run is finished (its verdict is stored) and a configuration value its
        stages were computed with differs from the new job's: ``--force`` replaces it.
    """
    if FINISHED_STAGE not in stored:
        return
    old = job_values(getattr(info, "key_inputs", "") for info in stored.values())
    new = job_values(planned.values())
    differing = sorted(k for k in old.keys() & new.keys() if old[k] != new[k])
    if not differing:
        return
    shown = ", ".join(differing[:6]) + (
        f" and {len(differing) - 6} more" if len(differing) > 6 else ""
    )
    raise DifferentJobError(
        f"{clip(str(directory))}: holds a finished run of another job ({clip(sources[0] or '?')}); "
        f"this job ({clip(sources[1] or '?')}) differs in {shown}: choose another --out, or give "
        "--force to replace that run"
    )


#: File name endings of what a report writes (report.md, report.html, figures, their CSVs).
REPORT_SUFFIXES = (".md", ".html", ".png", ".pdf", ".svg", ".csv")


def _report_files(directory: Path) -> dict[str, tuple[int, int]]:
    """The report-like files in ``directory``: name -> (inode, modification time, ns)."""
    found = {}
    with contextlib.suppress(OSError):
        for entry in os.scandir(directory):
            if entry.name.endswith(REPORT_SUFFIXES) and entry.is_file(follow_symlinks=False):
                info = entry.stat(follow_symlinks=False)
                found[entry.name] = (info.st_ino, info.st_mtime_ns)
    return found


@contextlib.contextmanager
def report_removed_on_failure(directory: str | Path) -> Iterator[None]:
    """Write a report inside the block; if it cannot finish, remove what it wrote.

    Every report file (:data:`REPORT_SUFFIXES`) the block created in ``directory`` is removed
    when the block ends by an exception (a full disk, Ctrl-C, a failing figure), and so are a
    report.md and report.html it created, which would otherwise point at figures that are
    gone: a half-written first report is never left beside ``results.h5``. A report of an
    earlier run that was there before is kept whole (each file is replaced atomically, so the
    one that failed is unchanged; nothing finished is deleted). A write error is re-raised
    with that said.
    """
    directory = Path(directory)
    before = _report_files(directory)
    try:
        yield
    except BaseException as exc:
        after = _report_files(directory)
        written = [name for name in after if name not in before]
        for name in written:
            with contextlib.suppress(OSError):
                (directory / name).unlink()
        if isinstance(exc, OutputWriteError) and written:
            removed = f"the unfinished report ({len(written)} new files) was removed"
            raise OutputWriteError(f"{exc}; {removed}", exc.errno) from exc
        raise
