"""Where a command writes, checked before it does any work.

Every command that writes a file (``-o FILE``) or into a folder (``--out
DIR``) asks here first, so that a path it cannot use is one typed error
naming the path and the operating system's reason ("Is a directory", "No
such file or directory", "Permission denied", ...), before any planning,
process or half-written file. A file output that is also one of the
command's inputs is refused too: writing it would destroy that input.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import logging
import os
import shutil
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path

from shared.errors import InvalidInputError
from shared.held_signals import held_signals

log = logging.getLogger("armplan.output")


def same_file(a: str | Path, b: str | Path) -> bool:
    """Whether ``a`` and ``b`` name one file (resolved, or one inode)."""
    if Path(a).resolve() == Path(b).resolve():
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def is_standard_output(path: str | Path, fd: int = 1) -> bool:
    """Whether ``path`` is the file this process's standard output writes to.

    ``-o /dev/stdout``, or the file or pipe stdout is redirected to: a
    command that also prints there would mix its own lines into the file.
    ``fd`` 2 asks it of standard error (``> play.py 2>&1``).
    """
    try:
        ours, theirs = os.fstat(fd), os.stat(path)
    except OSError:  # stdout closed, or no such file yet
        return False
    return (ours.st_dev, ours.st_ino) == (theirs.st_dev, theirs.st_ino)


def check_output_file(
    output: str | Path, inputs: Sequence[str | Path] = (), field: str = "output"
) -> Path:
    """``output`` as a path if the command may write that file.

    Args:
        output: The file to write, as the user gave it.
        inputs: Every file the command reads.
        field: The option's name, for the error's evidence.

    Raises:
        InvalidInputError: ``output`` is no file name (or ``-``, which
            other tools take for standard output), is a folder, lies in
            a folder that does not exist or cannot be written (a link's
            target, for a link to no file yet), or is one of ``inputs``.
    """
    path = Path(output)
    if not str(output) or path.name in ("", ".", ".."):
        raise InvalidInputError(
            f"output {str(output)!r} is not a file name", field=field
        )
    if str(output) == "-":  # the usual "standard output" wrote a file named -
        raise InvalidInputError(
            "output '-' would be a file named '-': give /dev/stdout to write "
            "to standard output (or ./- for a file named -)",
            field=field,
        )
    problem = _file_problem(path)
    if not problem and path.is_symlink() and not path.exists():  # dangling
        target = Path(os.path.realpath(path))  # written through the link
        problem = _file_problem(target)
        problem = f"{problem} (it links to {target})" if problem else ""
    if problem:
        raise InvalidInputError(f"cannot write {output}: {problem}", field=field)
    for name in inputs:
        if same_file(path, name):
            raise InvalidInputError(
                f"output {path} is also an input ({name}): writing it would "
                "destroy that input; choose another output name",
                field=field,
                input=str(name),
            )
    return path


def check_output_folder(out: str | Path, option: str = "--out") -> Path:
    """``out`` as a path if the command may write into that folder (made if missing).

    Args:
        out: The folder as the user gave it.
        option: The command-line option it came from, for the message.

    Raises:
        InvalidInputError: naming ``option``, the path and what is wrong.
    """
    field = option.lstrip("-")
    if not str(out):
        raise InvalidInputError(
            f"{option} is empty: name a folder (. for the current one)", field=field
        )
    problem = _folder_problem(Path(out))
    if problem:
        raise InvalidInputError(
            f"cannot write into {out} ({option}): {problem}", field=field, path=str(out)
        )
    return Path(out)


def make_output_folder(out: str | Path, option: str = "--out") -> Path:
    """Make folder ``out`` (and its parents) if missing; returns it.

    For the file systems whose refusal :func:`check_output_folder` cannot
    foresee (``/sys``, ``/proc``, read-only mounts).

    Raises:
        InvalidInputError: as :func:`check_output_folder` does, with the
            operating system's reason.
    """
    path = Path(out)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InvalidInputError(
            f"cannot write into {out} ({option}): {error.strerror}",
            field=option.lstrip("-"),
            path=str(out),
        ) from None
    return path


def try_output_folder(out: str | Path, option: str = "--out") -> Path:
    """Check that folder ``out`` can be made, and leave no trace of it.

    :func:`check_output_folder`, then the folders missing on the way to
    ``out`` are made (:func:`make_output_folder`, which finds what the check
    cannot foresee: ``/proc``, ``/sys``) and removed again, deepest first,
    so that a run that fails or is interrupted later leaves none behind;
    so are those made before a deeper one failed (no inode left, say).
    The command makes the folder when it writes.

    Raises:
        InvalidInputError: as :func:`check_output_folder` and
            :func:`make_output_folder` do.
    """
    path = check_output_folder(out, option)
    missing = [p for p in (path, *path.parents) if not p.exists()]
    try:
        make_output_folder(path, option)  # may fail below folders it made
    finally:
        for folder in missing:
            with contextlib.suppress(OSError):  # another run wrote into it
                folder.rmdir()
    return path


def write_output_text(path: str | Path, text: str, field: str = "output") -> Path:
    """Write ``text`` (UTF-8) to ``path``, whole or not at all; returns the path.

    Written to a partial file renamed over ``path`` when complete
    (:func:`replaced_when_done`): a write that fails part-way (a full disk,
    ``ulimit -f``) leaves an older file of that name as it was, not cut
    short. A file replaced keeps its permissions, and a symbolic link its
    target, which is the file replaced. A path that is no regular file (a
    device such as ``/dev/null``, a FIFO, ``/dev/stdout``) is written as it
    is: replacing it would put a regular file in its place.

    Raises:
        InvalidInputError: naming the path and the OS's reason if it cannot be
            written.
    """
    path = Path(path)
    try:
        write_whole(path, text)
    except OSError as exc:
        raise InvalidInputError(
            f"cannot write {path}: {exc.strerror}", field=field
        ) from None
    return path


def write_whole(path: Path, text: str) -> None:
    """:func:`write_output_text` raising the ``OSError``, for a caller's own error.

    A regular file (or a link's target) is replaced when the text is
    written, keeping its mode; anything else (``/dev/null``, ``/dev/full``,
    a FIFO) is written into: ``armplan fit -o /dev/full``, run as root, put
    a regular file in the device's place.

    Raises:
        OSError: the path cannot be written (``strerror`` says why).
    """
    with written_whole(path) as out:
        out.write_text(text, encoding="utf-8")


@contextlib.contextmanager
def written_whole(path: Path) -> Iterator[Path]:
    """The file to write for ``path``: a partial one renamed over it, if any.

    A regular file, or a link's target, is written under a ``.partial``
    name renamed over it when the block ends (:func:`replaced_when_done`),
    keeping its mode. The folder is held meanwhile (:func:`_one_writer_in`):
    two runs writing one file at once shared its partial file, and one
    failed "No such file or directory" or renamed the other's half-written
    one into place. A path that is no regular file (``/dev/null``, a FIFO,
    ``/dev/stdout``) is itself yielded, to write into: replacing it would
    put a regular file in its place. So is a path through ``/proc`` (a
    ``/dev/stdout`` redirected to a file, ``/dev/fd/3``): the file already
    open there was replaced, and what the shell wrote to it afterwards lost.
    """
    if path.exists() and (not path.is_file() or _an_open_file(path)):
        yield path  # followed as opened
        return
    target = Path(os.path.realpath(path))
    with _one_writer_in(target.parent), replaced_when_done(target) as partial:
        yield partial  # another run's partial file is not this one's
        with contextlib.suppress(FileNotFoundError):
            shutil.copymode(target, partial)


def _an_open_file(path: Path) -> bool:
    """Whether ``path`` or a link on the way leads into ``/proc`` (``/dev/stdout``).

    ``/proc/self/fd/1`` reads as the file it is open on, a redirected
    ``>> run.log`` for one: renaming a new file over that replaced the log,
    and the lines the shell wrote after went to the replaced one.
    """
    hop = path
    for _ in range(40):  # the kernel's limit of links followed
        if Path(os.path.realpath(hop.parent)).is_relative_to("/proc"):
            return True
        if not hop.is_symlink():
            return False
        hop = hop.parent / os.readlink(hop)
    return False


@contextlib.contextmanager
def replaced_when_done(path: Path) -> Iterator[Path]:
    """A ``<name>.partial`` file to write, renamed to ``path`` when the block ends.

    A reader never sees half a file, and if the block raises, ``path`` (an
    older file of that name) is left as it was and the partial file removed.
    ``OSError`` from the rename propagates to the caller, for its own error.
    """
    partial = path.with_name(path.name + ".partial")
    try:
        yield partial
        os.replace(partial, path)
    finally:
        with contextlib.suppress(OSError):
            partial.unlink()


class PartialFiles(list[Path]):
    """The ``<name>.partial`` files of :func:`replaced_together`, in its order.

    A list of paths (unpacked as one), and :meth:`write_text`, which notes
    the file it writes: a ``write()`` that fails (a full disk, ``ulimit
    -f``, an I/O error) raises an ``OSError`` without a file name, and the
    note is how the error names the file.

    Attributes:
        writing: The partial file being written by :meth:`write_text`, or
            ``None`` between writes.
    """

    def __init__(self, partials: Sequence[Path]) -> None:
        super().__init__(partials)
        self.writing: Path | None = None

    def write_text(self, partial: Path, text: str) -> None:
        """Write ``text`` (UTF-8) to ``partial``, one of these files."""
        self.writing = partial
        partial.write_text(text, encoding="utf-8")
        self.writing = None


@contextlib.contextmanager
def replaced_together(
    paths: Sequence[Path], field: str = "out"
) -> Iterator[PartialFiles]:
    """``<name>.partial`` files to write, renamed to ``paths`` when the block ends.

    For files that belong together (an experiment's JSON, tables and
    figures): the block writes each under its partial name, and only then
    are they all renamed. If the block raises (a failed write, Ctrl-C), or
    a path cannot be replaced by a file (a folder stands there), no path is
    touched: an older set of these files stays whole, not half new. The
    partial files are removed in every case. The renames run with the stop
    signals held (:mod:`shared.held_signals`): a Ctrl-C or SIGTERM that
    comes between two of them (it left the set half new) takes effect
    after the last one, the new set whole.

    One process at a time writes sets into a folder (:func:`_one_writer_in`):
    two runs writing the same set at once used to share its partial files,
    so one renamed the other's and the other failed ("No such file or
    directory"), leaving a set mixed of both runs. The second now waits
    for the first's set to be written, and then replaces it whole.

    An ``OSError`` the block raises is this function's typed error if it
    names a partial file, or, without a file name (a failed ``write()``),
    if it came from :meth:`PartialFiles.write_text`.

    Args:
        paths: The files to write, in one folder.
        field: The option naming the folder, for the error's evidence.

    Raises:
        InvalidInputError: naming the file that cannot be written or
            replaced (not its partial name), and the operating system's reason.
    """
    partials = PartialFiles([path.with_name(path.name + ".partial") for path in paths])
    with (
        _one_writer_in(paths[0].parent if paths else None),
        _renamed(partials, paths, field),
    ):
        yield partials


@contextlib.contextmanager
def _one_writer_in(folder: Path | None) -> Iterator[None]:
    """Hold ``folder`` for this block: an exclusive ``flock`` on the folder itself.

    Another process or thread holding it (writing its set) is waited for;
    the lock goes with the block, or with the process however it ends, and
    leaves no file behind. A folder that cannot be opened or locked
    (missing, a file system without ``flock``) is written without it, as
    before. A folder this thread already holds (a set written while
    writing another into it) is not locked again: its second ``flock``
    waited for the first, forever.
    """
    held: set[tuple[int, int]] = vars(_HELD).setdefault("folders", set())
    try:
        fd: int | None = (
            os.open(folder, os.O_RDONLY | os.O_DIRECTORY) if folder else None
        )
    except OSError:
        fd = None
    key: tuple[int, int] | None = None
    try:
        if fd is not None:
            info = os.fstat(fd)
            if (info.st_dev, info.st_ino) not in held:
                _lock(fd, folder)
                key = (info.st_dev, info.st_ino)
                held.add(key)
        yield
    finally:
        if key is not None:
            held.discard(key)
        if fd is not None:
            os.close(fd)


#: Per thread, the folders (device, inode) :func:`_one_writer_in` holds.
_HELD = threading.local()


def _lock(fd: int, folder: Path | None) -> None:
    """Take ``folder``'s lock (its open ``fd``); say so if another holds it.

    A wait is announced (a warning on stderr), or a writer suspended with
    Ctrl-Z in the same folder would hold this one up without a word. A file
    system without ``flock`` leaves the folder unlocked.
    """
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return
    except BlockingIOError:
        log.warning("waiting for another armplan run writing into %s to finish", folder)
    except OSError:
        return
    with contextlib.suppress(OSError):
        fcntl.flock(fd, fcntl.LOCK_EX)


@contextlib.contextmanager
def _renamed(
    partials: PartialFiles, paths: Sequence[Path], field: str
) -> Iterator[None]:
    """:func:`replaced_together`'s renaming and clean-up, the folder held."""
    try:
        try:
            yield
        except OSError as exc:  # name the file asked for, not its partial
            final = dict(zip(map(str, partials), paths, strict=True))
            named = partials.writing if exc.filename is None else exc.filename
            path = final.get(str(named))
            if path is None:
                raise
            raise InvalidInputError(
                f"cannot write {path}: {exc.strerror}", field=field
            ) from None
        for path in paths:
            if path.is_dir():
                raise InvalidInputError(
                    f"cannot write {path}: {os.strerror(errno.EISDIR)}", field=field
                )
        with held_signals():  # Ctrl-C between two renames left a mixed set
            for partial, path in zip(partials, paths, strict=True):
                try:
                    os.replace(partial, path)
                except OSError as exc:
                    raise InvalidInputError(
                        f"cannot write {path}: {exc.strerror}", field=field
                    ) from None
    finally:
        for partial in partials:
            with contextlib.suppress(OSError):
                partial.unlink()


def _file_problem(path: Path) -> str:
    """Why no file can be written at ``path`` (the OS's words), or ``""``."""
    folder = path.parent
    if path.is_dir():
        code = errno.EISDIR
    elif not folder.exists():
        code = errno.ENOENT
    elif not folder.is_dir():
        code = errno.ENOTDIR
    elif path.exists():
        code = 0 if os.access(path, os.W_OK) else _denied(path)
    else:
        code = 0 if os.access(folder, os.W_OK | os.X_OK) else _denied(folder)
    return os.strerror(code) if code else ""


def _denied(path: Path) -> int:
    """Why ``path`` may not be written: ``EROFS`` or ``EACCES``.

    ``EROFS`` on a read-only file system (a read-only mount, as a
    container's volume may be), else ``EACCES``.

    ``os.access`` says only no; "Permission denied" on a read-only mount
    sent the user to permissions that are not the cause.
    """
    try:
        read_only = bool(os.statvfs(path).f_flag & os.ST_RDONLY)
    except OSError:
        read_only = False
    return errno.EROFS if read_only else errno.EACCES


def _folder_problem(path: Path) -> str:
    """Why no files can be written into folder ``path``, or ``""``."""
    try:
        return _folder_access_problem(path)
    except OSError as error:  # a name too long, a loop of links
        return str(error.strerror)


def _folder_access_problem(path: Path) -> str:
    """:func:`_folder_problem`; raises ``OSError`` if ``path`` cannot be looked up."""
    if path.exists() and not path.is_dir():
        return "it is a file, not a folder"
    existing = next(p for p in (path, *path.parents) if p.exists())
    if not existing.is_dir():
        return f"{existing} is a file, not a folder"
    if not os.access(existing, os.W_OK | os.X_OK):
        return f"{existing}: {os.strerror(_denied(existing))}"
    return ""
