"""One demo per output folder: a second run into the same folder is refused.

Two demos writing one folder mixed their simulators' logs and processes'
logs, and one of them failed on a recording the other had replaced. The
folder is claimed with an exclusive ``flock`` on a hidden file in it, held
for the run (the kernel releases it when the process ends, however it ends)
and removed afterwards.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from shared.errors import InvalidInputError
from shared.output_paths import make_output_folder

#: The claim file inside the output folder.
CLAIM_FILE = ".armplan-demo.lock"


@contextlib.contextmanager
def claimed_folder(out: Path) -> Iterator[Path]:
    """Hold ``out`` (made if missing) for this run; yields it.

    Raises:
        InvalidInputError: another running demo holds ``out`` (naming its
            PID), or ``out`` or the claim file cannot be made.
    """
    make_output_folder(out)
    path = out / CLAIM_FILE
    fd = _claim(out, path)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        try:
            yield out
        finally:
            path.unlink(missing_ok=True)  # while held: no one holds it after
    finally:
        os.close(fd)


def _claim(out: Path, path: Path) -> int:
    """The claim file's descriptor, locked; raises if another run holds it.

    A lock won on a file its holder removed on the way out (opened just
    before) claims nothing: the next run would make and lock a new file. So
    the locked file must still be the one at ``path``, or it is tried again.
    """
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as error:
            raise InvalidInputError(
                f"cannot claim the output folder {out}: {error.strerror}", field="out"
            ) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _holder(fd)
            os.close(fd)
            raise InvalidInputError(
                f"{out} is the output folder of another armplan demo still running"
                f"{holder}: wait for it, or give another --out",
                field="out",
            ) from None
        if _same_file(fd, path):
            return fd
        os.close(fd)  # its holder removed it meanwhile: claim the new one


def _same_file(fd: int, path: Path) -> bool:
    """Whether ``fd`` is the file now at ``path``."""
    try:
        at_path = os.stat(path)
    except FileNotFoundError:
        return False
    held = os.fstat(fd)
    return (held.st_dev, held.st_ino) == (at_path.st_dev, at_path.st_ino)


def _holder(fd: int) -> str:
    """`` (pid N)`` from the claim file, or nothing if it does not say."""
    text = os.pread(fd, 32, 0).decode(errors="replace").strip()
    return f" (pid {text})" if text.isdigit() else ""
