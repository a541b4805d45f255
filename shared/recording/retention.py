"""Removing the oldest parts of a rotating recording (``--keep-parts``).

A recorder left running all day with rotation fills the disk; with a number
of parts to keep, each time a part is closed and the next one started, the
parts before the newest ``keep`` (the one being written counted) are
removed. Only files the writer created itself in this run are removed: each
part is remembered by its device and inode when it is created (exclusively),
and by its size and modification time when it is closed with its summary
(both by its descriptor, never by name), and removed only if it was closed
and its path still names that very file, is not a symbolic link, and no
other writer holds it (``file_lock``). The inode alone is not enough: ext4
gives a freed inode to the next file made, so a part someone deleted and a
file then put at its name (a restored copy) would look the same. A removal
that fails is a warning naming the file; it never stops the recording.

Between the last check and the unlink (by name: there is no unlink by
descriptor) the part is locked, so no armplan writer can replace it; only
a rename onto that name by another program in that instant could be
removed instead.
"""

from __future__ import annotations

import logging
import os
import stat
from dataclasses import dataclass
from pathlib import Path

from shared.recording.file_lock import try_hold

log = logging.getLogger("armplan.recording")


@dataclass(frozen=True)
class OwnPart:
    """A part this writer created: its path and the file it named then.

    Attributes:
        path: The part's path.
        device: The file's device (``st_dev``).
        inode: The file's inode (``st_ino``).
        closed: The file as closed with its summary (``MessageWriter.final``);
            ``None`` while it is written.
    """

    path: Path
    device: int
    inode: int
    closed: os.stat_result | None = None

    def names(self, info: os.stat_result) -> bool:
        """Whether ``info`` is the file this part was created and closed as."""
        closed = self.closed
        return (
            closed is not None
            and (info.st_dev, info.st_ino) == (self.device, self.inode)
            and (info.st_size, info.st_mtime_ns) == (closed.st_size, closed.st_mtime_ns)
        )


def parts_to_remove(parts: list[OwnPart], keep: int) -> list[OwnPart]:
    """The oldest of ``parts`` (in order) beyond the newest ``keep``."""
    return parts[: max(len(parts) - keep, 0)]


def remove_part(part: OwnPart) -> int | None:
    """Remove ``part`` if it is still the file created; its size [bytes], else None.

    Left in place (a warning naming it): a part not closed with its summary,
    a path that is gone, is a symbolic link, names another file now, is held
    by another writer, or whose removal the file system refuses.
    """
    if part.closed is None:  # never so for a part before the newest
        _left(part.path, "it was not closed with its summary")
        return None
    try:
        fd = os.open(part.path, os.O_RDONLY | os.O_NOFOLLOW)
    except OSError as error:
        _left(part.path, error.strerror or str(error))
        return None
    try:
        info = os.fstat(fd)
        if not (stat.S_ISREG(info.st_mode) and part.names(info)):
            _left(part.path, "it is no longer the file this recorder wrote")
            return None
        if not try_hold(fd):
            _left(part.path, "another recorder holds it")
            return None
        if not part.names(os.lstat(part.path)):  # replaced before the lock
            _left(part.path, "it is no longer the file this recorder wrote")
            return None
        part.path.unlink()
    except OSError as error:
        _left(part.path, error.strerror or str(error))
        return None
    finally:
        os.close(fd)
    log.info("recording: removed old part %s (%d bytes)", part.path, info.st_size)
    return info.st_size


def _left(path: Path, why: str) -> None:
    """Warn that an old part was not removed."""
    log.warning("recording: could not remove old part %s: %s; left", path, why)
