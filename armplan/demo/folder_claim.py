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

#: The claim file inside the output folder.
CLAIM_FILE = ".armplan-demo.lock"


@contextlib.contextmanager
def claimed_folder(out: Path) -> Iterator[Path]:
    """Hold ``out`` (made if missing) for this run; yields it.

    Raises:
        InvalidInputError: another running demo holds ``out`` (naming its
            PID), or the claim file cannot be made.
    """
    out.mkdir(parents=True, exist_ok=True)
    path = out / CLAIM_FILE
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        raise InvalidInputError(
            f"cannot claim the output folder {out}: {error.strerror}", field="out"
        ) from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise InvalidInputError(
                f"{out} is the output folder of another armplan demo still running"
                f"{_holder(fd)}: wait for it, or give another --out",
                field="out",
            ) from None
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        try:
            yield out
        finally:
            path.unlink(missing_ok=True)
    finally:
        os.close(fd)


def _holder(fd: int) -> str:
    """`` (pid N)`` from the claim file, or nothing if it does not say."""
    text = os.pread(fd, 32, 0).decode(errors="replace").strip()
    return f" (pid {text})" if text.isdigit() else ""
