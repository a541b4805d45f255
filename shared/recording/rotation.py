"""A live MCAP recording split into numbered files by size or by duration.

Without a limit the recording is one file, exactly the path given. With a
size or duration limit it is ``<stem>-0001.mcap``, ``<stem>-0002.mcap``, ...
beside that path: when the current file has reached ``max_bytes`` or has been
open for ``max_seconds``, it is closed properly (its summary written) and
the next message starts the next file. With ``keep_parts`` N, the parts
before the newest N are then removed (``retention``). Every file is complete on its own:
the ``on_open`` hook writes what each file needs first (metadata, the robot
description), and channels and schemas are registered again in each file.
"""

from __future__ import annotations

import glob
import os
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from shared.errors import InvalidInputError, RecordingError
from shared.lifecycle import Closes
from shared.recording.file_lock import busy_error, held_by_another, locked_all
from shared.recording.retention import OwnPart, parts_to_remove, remove_part
from shared.recording.writer import MessageWriter, refuse_folder

#: Default longest time between flushes of a live file [s].
FLUSH_EVERY = 0.2
#: The longest time between flushes allowed [s]: more, and a killed recorder
#: loses too much.
MAX_FLUSH_EVERY = 10.0


@dataclass(frozen=True)
class RotationPolicy:
    """When to start a new file, and how many to keep.

    Attributes:
        max_bytes: Start a new file once the current one holds this much
            [bytes]; ``None`` for no size limit.
        max_seconds: Start a new file once the current one has been open this
            long [s]; ``None`` for no time limit.
        keep_parts: Keep only the newest this many parts (the one being
            written counted), removing older ones of this recording as new
            ones start; ``None`` keeps them all. Only with a limit.
    """

    max_bytes: int | None = None
    max_seconds: float | None = None
    keep_parts: int | None = None

    def __post_init__(self) -> None:
        if self.max_bytes is not None and self.max_bytes <= 0:
            raise InvalidInputError(
                f"rotation size must be positive, got {self.max_bytes} bytes",
                field="max_bytes",
            )
        if self.max_seconds is not None and not self.max_seconds > 0:
            raise InvalidInputError(
                f"rotation duration must be positive, got {self.max_seconds} s",
                field="max_seconds",
            )
        if self.keep_parts is not None:
            self._check_keep_parts(self.keep_parts)

    def _check_keep_parts(self, keep: int) -> None:
        """Refuse a count below 1, or a count without a limit to rotate by."""
        if isinstance(keep, bool) or not isinstance(keep, int) or keep < 1:
            raise InvalidInputError(
                "--keep-parts must be a whole number of files, at least 1, "
                f"got {keep!r}",
                field="keep_parts",
            )
        if not self.rotates:
            raise InvalidInputError(
                "--keep-parts needs --rotate-size or --rotate-duration: without "
                "rotation the recording is one file",
                field="keep_parts",
            )

    @property
    def rotates(self) -> bool:
        """Whether the recording may span several files."""
        return self.max_bytes is not None or self.max_seconds is not None


def part_path(path: Path, number: int) -> Path:
    """The path of file ``number`` (1, 2, ...) of a rotating recording at ``path``.

    Example: ``session.mcap``, 3 -> ``session-0003.mcap``.
    """
    return path.with_name(f"{path.stem}-{number:04d}{path.suffix or '.mcap'}")


#: Most files a message names one by one; beyond, the first and the last.
NAMED_PARTS = 3


def parts_named(paths: list[Path]) -> str:
    """``paths`` for a message: all of a few, else ``first ... last (N files)``.

    A day's recording rotated every 5 minutes is 288 files: listed whole, the
    recorder's last line ran to 288 paths.
    """
    if len(paths) <= NAMED_PARTS:
        return ", ".join(map(str, paths))
    return f"{paths[0]} ... {paths[-1]} ({len(paths)} files)"


def numbered_parts(path: Path) -> list[Path]:
    """The numbered files of a rotating recording at ``path`` now, in order.

    Four digits, or five for parts 10000 to 99999, in the order of their
    numbers: part 10000 follows 9999 (``--keep-parts`` lets a recorder run
    that long), although its name sorts before it. No more digits: a file
    named with a date (``s-20261127.mcap``) is not taken for a part, to be
    refused or removed by ``--overwrite``.
    """
    suffix = path.suffix or ".mcap"
    pattern = f"{glob.escape(path.stem)}-[0-9][0-9][0-9][0-9]*{glob.escape(suffix)}"
    number = "[0-9]{4}|[1-9][0-9]{4}"
    name = re.compile(f"{re.escape(path.stem)}-({number}){re.escape(suffix)}")
    found = []
    for part in path.parent.glob(pattern):
        if match := name.fullmatch(part.name):
            found.append((int(match.group(1)), part))
    return [part for _, part in sorted(found)]


class RotatingWriter(Closes):
    """Live-layout MCAP files, numbered, each closed with its summary.

    Not thread-safe: one thread writes (the recorder's writer thread).

    Args:
        path: The recording's path (the file itself when nothing rotates).
        policy: When to start a new file.
        on_open: Called with each new file's writer and its number before
            anything else is written to it.
        flush_every: Longest time between flushes to the OS [s].
        overwrite: Replace an existing recording at ``path`` (with rotation:
            its numbered files, all of them removed on opening); if False, an
            existing one is refused. Either way a recording another writer
            is still writing is refused (``file_lock``): the first file stays
            held for the whole recording (with ``keep_parts``, until it is
            removed; then the part started then, and so on), the current
            one while it is written; the files after the first are created
            exclusively.

    Attributes:
        paths: Every file started so far and not removed, in order.
        pruned: Parts removed by ``policy.keep_parts`` so far, in order.
        pruned_bytes: Their sizes together [bytes].
    """

    def __init__(
        self,
        path: str | Path,
        policy: RotationPolicy | None = None,
        on_open: Callable[[MessageWriter, int], None] | None = None,
        flush_every: float = FLUSH_EVERY,
        *,
        overwrite: bool = False,
    ) -> None:
        self.path = Path(path)
        self.overwrite = overwrite
        self.policy = policy or RotationPolicy()
        self.paths: list[Path] = []
        self.pruned: list[Path] = []
        self.pruned_bytes = 0
        self._own: list[OwnPart] = []  # the parts in paths, as created
        self._number = 0  # of the last file started
        self._on_open = on_open
        self._flush_every = flush_every
        self._writer: MessageWriter | None = None
        self._opened = 0.0
        self._claim: int | None = None  # holds the first file until close
        self._claimed: Path | None = None  # the file it holds
        self.closed = False

    @property
    def started(self) -> int:
        """How many files were started so far, removed ones included."""
        return self._number

    @property
    def writer(self) -> MessageWriter:
        """The current file's writer, opening the first (or next) file if needed."""
        if self._writer is None or self._due():
            self._next()
        assert self._writer is not None
        return self._writer

    def open(self) -> RotatingWriter:
        """Start the first file now (else the first message starts it).

        Raises:
            RecordingError: if the recording exists (and ``overwrite`` is
                False), ``path`` is a folder, or the file cannot be created.
        """
        if self._writer is None:
            self._next()
        return self

    def _earlier_parts(self) -> list[Path]:
        """Numbered files of an earlier recording at this path, in order."""
        return numbered_parts(self.path) if self.policy.rotates else []

    def _clear_earlier(self) -> None:
        """Remove (``overwrite``) or refuse an earlier rotating recording.

        Either all of its files are removed or none: none while another
        writer holds one of them (it is still recording).
        """
        earlier = self._earlier_parts()
        if not self.overwrite:
            for part in earlier:  # still recording: not "an earlier recording"
                if held_by_another(part):
                    raise busy_error(part)
        if earlier and not self.overwrite:
            more = len(earlier) - 1
            which = (
                f"{earlier[0]} and {more} more numbered files" if more else earlier[0]
            )
            verb = "exist" if more else "exists"
            raise RecordingError(
                f"{which} of an earlier recording {verb}: give another name, or "
                "--overwrite to replace them",
                path=str(earlier[0]),
            )
        with locked_all(earlier):
            for part in earlier:
                part.unlink(missing_ok=True)

    def _due(self) -> bool:
        """Whether the current file has reached a limit."""
        assert self._writer is not None
        limit_bytes, limit_s = self.policy.max_bytes, self.policy.max_seconds
        full = limit_bytes is not None and self._writer.size >= limit_bytes
        old = limit_s is not None and time.monotonic() - self._opened >= limit_s
        return full or old

    def _next(self) -> None:
        """Close the current file (if any) and open the next one."""
        if self._writer is not None:
            self._writer.close()
            last = self._own[-1]  # known by its size and time from now on
            self._own[-1] = replace(last, closed=self._writer.final)
        number = self._number + 1
        if number == 1:
            refuse_folder(self.path)  # its parts would go beside it, not in it
            self._clear_earlier()
        path = part_path(self.path, number) if self.policy.rotates else self.path
        self._writer = MessageWriter(
            path,
            chunked=False,
            flush_every=self._flush_every,
            overwrite=self.overwrite and number == 1,  # the rest were removed
        )
        if number == 1 and self.policy.rotates:
            self._claim, self._claimed = self._writer.hold(), path
        self._number = number
        self._opened = time.monotonic()
        self.paths.append(path)
        self._own.append(OwnPart(path, *self._writer.identity))
        if self._on_open is not None:
            self._on_open(self._writer, number)
        self._prune()

    def _prune(self) -> None:
        """Remove the parts before the newest ``policy.keep_parts``.

        The hold on the recording (first on part 1) moves to the part just
        started first: a part this writer holds itself would look held by
        another.
        """
        keep = self.policy.keep_parts
        if keep is None:
            return
        old = parts_to_remove(self._own, keep)
        if not old:
            return
        assert self._writer is not None
        if self._claim is not None and any(p.path == self._claimed for p in old):
            self._release()
            self._claim, self._claimed = self._writer.hold(), self.paths[-1]
        for part in old:
            size = remove_part(part)
            if size is not None:
                self.pruned.append(part.path)
                self.pruned_bytes += size
        del self._own[: len(old)]
        del self.paths[: len(old)]

    def write(
        self,
        topic: str,
        schema_name: str,
        schema: dict[str, Any],
        data: bytes,
        log_time: int,
        publish_time: int,
        *,
        may_rotate: bool = True,
        metadata: dict[str, str] | None = None,
    ) -> None:
        """Append one JSON message (rotating first if a limit was reached).

        Args:
            topic: Channel topic.
            schema_name: Name of the channel's schema, e.g. ``"Trajectory"``.
            schema: The JSON schema.
            data: The message's JSON [UTF-8 bytes].
            log_time: When the message was made [ns since the epoch].
            publish_time: When it was received [ns since the epoch].
            may_rotate: ``False`` keeps the message in the current file even
                past a limit (what a message derives stays beside it).
            metadata: The channel's metadata (a channel per topic, schema
                and metadata), e.g. ``{"zenoh_encoding": "application/json"}``.
        """
        writer = self.writer if may_rotate or self._writer is None else self._writer
        channel = writer.add_channel(topic, schema_name, schema, metadata)
        writer.write_raw(channel, data, log_time, publish_time)

    def flush(self) -> None:
        """Push everything written so far to the OS."""
        if self._writer is not None:
            self._writer.flush()

    def close(self) -> None:
        """Close the current file with its summary. Safe to call twice."""
        try:
            if self._writer is not None:
                self._writer.close()
        finally:
            self._release()
            self.closed = True

    def _release(self) -> None:
        """Let go of the first file (another writer may replace it now)."""
        if self._claim is not None:
            os.close(self._claim)
            self._claim = None
