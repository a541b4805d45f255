"""Recording files held by their writer: refused to another while written.

A writer opens its file with :func:`open_locked`, which takes an advisory
lock (``flock`` exclusive) on it and keeps it for as long as the file is
open. Another writer asked to replace the file (``--overwrite``) or to
remove it (the numbered files of a rotating recording) first tries the
lock: a file another writer holds is refused, so two recorders never share
one, and a recording still being written is never cut short. A file is
replaced by unlinking it and creating a new one exclusively, never by
truncating it in place: a writer that still had it open would go on
writing into the emptied file.

The lock is advisory: readers (``inspect``, a replay) do not take it and
read a file being written as before.
"""

from __future__ import annotations

import fcntl
import os
import stat
from collections.abc import Iterator, Sequence
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import IO

from shared.errors import RecordingError

#: Permissions of a new recording (before the umask), as ``open(..., "wb")``.
MODE = 0o666


def busy_error(path: Path) -> RecordingError:
    """The error for a file another recorder is writing."""
    return RecordingError(
        f"{path} is being written by another recorder: give another name "
        "(--overwrite never replaces a recording still being written)",
        path=str(path),
    )


def exists_error(path: Path) -> RecordingError:
    """The error for an existing file that is not to be replaced."""
    return RecordingError(
        f"{path} exists: give another name, or --overwrite to replace it",
        path=str(path),
    )


def held_by_another(path: Path) -> bool:
    """Whether another writer holds the existing ``path`` (it is recording).

    Used to say so when an existing file is refused without ``--overwrite``:
    "exists: ... --overwrite to replace it" sent the user to an option that
    is refused too. The lock is tried, and let go at once if taken.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError:  # gone, a link to nothing, unreadable: not known held
        return False
    try:
        return not try_hold(fd)
    except OSError:  # the file system takes no lock
        return False
    finally:
        os.close(fd)


def refuse_existing(path: Path) -> RecordingError:
    """The error for an existing ``path`` not to be replaced: busy or exists."""
    return busy_error(path) if held_by_another(path) else exists_error(path)


def dangling_error(path: Path) -> RecordingError:
    """The error for a symbolic link whose target does not exist."""
    try:
        target = os.readlink(path)
    except OSError:
        target = "?"
    return RecordingError(
        f"{path} is a symbolic link to {target}, which does not exist: "
        "--overwrite does not create a file where a dangling link points; "
        "remove the link or give another name",
        path=str(path),
    )


def pipe_error(path: Path, mode: int) -> RecordingError:
    """The error for a named pipe or a socket at ``path`` (``mode``: its stat's).

    A recording is written to a file it can tell its position in: into a
    pipe with a reader it failed "Illegal seek"; without one, the open
    waited for a reader for ever, deaf to Ctrl-C and SIGTERM.
    """
    kind = "a named pipe" if stat.S_ISFIFO(mode) else "a socket"
    return RecordingError(
        f"{path} is {kind}, not a file: a recording is written to a file "
        "(its writer needs to know its position in it); give a file's name",
        path=str(path),
    )


def _refuse_pipe(path: Path) -> None:
    """Refuse ``path`` if it is (or links to) a named pipe or a socket.

    Raises:
        RecordingError: :func:`pipe_error`.
    """
    try:
        mode = os.stat(path).st_mode
    except OSError:  # gone, or a link to nothing: the caller tells
        return
    if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
        raise pipe_error(path, mode)


def _refuse_opened_pipe(fd: int, path: Path) -> None:
    """Refuse the opened ``fd`` if it is a named pipe or a socket; else block.

    ``path`` was checked before it was opened (:func:`_refuse_pipe`), but
    could have been replaced since; ``fd`` was opened not blocking, so that
    such a pipe is seen here, not waited on. Writes to ``fd`` block again.

    Raises:
        RecordingError: :func:`pipe_error` (``fd`` closed).
    """
    mode = os.fstat(fd).st_mode
    if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
        os.close(fd)
        raise pipe_error(path, mode)
    os.set_blocking(fd, True)


def _lock(fd: int, path: Path) -> None:
    """Take the exclusive lock of ``fd`` without waiting; close it if held.

    Raises:
        RecordingError: :func:`busy_error` if another writer holds it.
        OSError: if the file system takes no lock (``fd`` closed too).
    """
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise busy_error(path) from None
    except OSError:
        os.close(fd)
        raise


def _same_file(fd: int, path: Path) -> bool:
    """Whether ``path`` still names the file open at ``fd``."""
    try:
        now = os.stat(path)
    except FileNotFoundError:
        return False
    held = os.fstat(fd)
    return (now.st_dev, now.st_ino) == (held.st_dev, held.st_ino)


def _create(path: Path) -> int:
    """A new file at ``path``, created exclusively and locked.

    Raises:
        FileExistsError: if ``path`` exists.
        RecordingError: if another writer replaced it before it was locked.
    """
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, MODE)
    _lock(fd, path)
    if not _same_file(fd, path):  # replaced between the create and the lock
        os.close(fd)
        raise busy_error(path)
    return fd


def _take_over(path: Path) -> int | None:
    """Replace the existing ``path``, unless another writer holds it.

    A regular file is unlinked (while locked, so no writer takes it
    meanwhile) and ``None`` returned: the caller creates a new one. Anything
    else (a device such as ``/dev/full``, a symbolic link) is opened for
    writing, locked, and a regular file behind a link emptied: its
    descriptor.

    Raises:
        RecordingError: if another writer holds it, it is a symbolic link
            to nothing (:func:`dangling_error`), or a named pipe or a socket
            (:func:`pipe_error`), or links to one.
        OSError: if it cannot be opened.
    """
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:  # removed meanwhile: create it
        return None
    _refuse_pipe(path)
    regular = stat.S_ISREG(mode)
    try:  # not blocking: a pipe put there since the check would wait for ever
        fd = os.open(path, (os.O_RDONLY if regular else os.O_WRONLY) | os.O_NONBLOCK)
    except FileNotFoundError:  # removed meanwhile, or a link to nothing
        if stat.S_ISLNK(mode) and os.path.islink(path):
            raise dangling_error(path) from None
        return None
    except OSError as exc:  # ENXIO: a pipe with no reader, put there meanwhile
        _refuse_pipe(path)
        raise exc from None
    _refuse_opened_pipe(fd, path)
    _lock(fd, path)
    try:
        if regular:
            path.unlink(missing_ok=True)
            return None
        if stat.S_ISREG(os.fstat(fd).st_mode):
            os.ftruncate(fd, 0)
        kept, fd = fd, -1  # the caller's now
        return kept
    finally:
        if fd >= 0:
            os.close(fd)


def open_locked(path: Path, *, overwrite: bool) -> IO[bytes]:
    """``path`` opened for writing, held (locked) until the file is closed.

    Args:
        path: The file.
        overwrite: Replace an existing file (unless another writer holds it);
            if False, an existing one is refused.

    Raises:
        RecordingError: if ``path`` exists (and ``overwrite`` is False) or
            another writer holds it.
        OSError: if the file system refuses to create or open it
            (``IsADirectoryError`` for a folder).
    """
    for _ in range(2):  # a second time if another writer made it meanwhile
        try:
            return os.fdopen(_create(path), "wb")
        except FileExistsError:
            if not overwrite:
                raise refuse_existing(path) from None
        fd = _take_over(path)
        if fd is not None:
            return os.fdopen(fd, "wb")
    raise busy_error(path)  # made again by another writer as it was replaced


def hold(stream: IO[bytes]) -> int:
    """A second descriptor on ``stream``'s file, holding its lock.

    It keeps the lock when the stream is closed, until ``os.close`` closes it.
    """
    return os.dup(stream.fileno())


def try_hold(fd: int) -> bool:
    """Take the lock of ``fd`` without waiting; False if another writer holds it.

    Raises:
        OSError: if the file system takes no lock.
    """
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


@contextmanager
def locked_all(paths: Sequence[Path]) -> Iterator[None]:
    """Hold the lock of every one of ``paths`` (none held by another writer).

    Used before removing them: either none is removed or all are, and none
    another writer is writing.

    Raises:
        RecordingError: naming the first file another writer holds.
    """
    with ExitStack() as stack:
        for path in paths:
            try:
                fd = os.open(path, os.O_RDONLY)
            except FileNotFoundError:
                continue
            _lock(fd, path)
            stack.callback(os.close, fd)
        yield
