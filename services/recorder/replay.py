"""A recording's messages, sent again with their original timing, scaled.

:func:`replay_items` reads the recorded Zenoh messages of a file (not the
derived ``/...`` Foxglove channels) in file order, which is the order the
recorder received them, with each one's offset from the first [s] (from the
log times) and its original bytes (a ``RawPayload`` is unwrapped). Keys are
made relative to the recorded namespace, so a replay may publish under
another one. :func:`replay` sends them through a ``publish`` function at
``offset / speed`` after the start; the caller supplies the Zenoh put.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from itertools import pairwise
from pathlib import Path
from typing import NamedTuple

import zenoh

from shared.errors import InvalidInputError, RecordingError
from shared.recording.metadata import ARMPLAN_METADATA, read_metadata
from shared.recording.raw_payload import RawPayload
from shared.recording.reader import Record, Recording

#: Encoding of the JSON messages when sent again.
JSON_ENCODING = "application/json"
_NS_PER_S = 1e9

Publish = Callable[[str, bytes, str], None]


class ReplayItem(NamedTuple):
    """One message to send again.

    Attributes:
        offset: Its log time minus the first message's [s].
        path: Its key relative to the recorded namespace, e.g. ``plan/trajectory``.
        payload: Its original bytes.
        encoding: Its Zenoh encoding.
    """

    offset: float
    path: str
    payload: bytes
    encoding: str


class ReplayStats(NamedTuple):
    """What a replay sent.

    Attributes:
        sent: Messages sent.
        duration: Wall time from the first to the last send [s].
        late: Largest delay of a send behind its scheduled time [s].
    """

    sent: int
    duration: float
    late: float


def _matcher(keys: Sequence[str] | None) -> Callable[[str], bool]:
    """Whether a relative key matches one of ``keys`` (all if ``None``)."""
    if not keys:
        return lambda path: True
    try:
        exprs = [zenoh.KeyExpr(f"r/{key}") for key in keys]
    except zenoh.ZError:
        raise InvalidInputError(
            f"--keys {' '.join(keys)}: not Zenoh key expressions", field="keys"
        ) from None
    return lambda path: any(e.intersects(f"r/{path}") for e in exprs)


def _item(record: Record, namespace: str, first: int) -> ReplayItem:
    path = record.topic.removeprefix(f"{namespace}/") if namespace else record.topic
    offset = (record.log_time - first) / _NS_PER_S
    if record.schema == RawPayload.__name__:
        raw = RawPayload.model_validate_json(record.raw)
        return ReplayItem(offset, path, raw.payload(), raw.encoding)
    return ReplayItem(offset, path, record.raw, JSON_ENCODING)


def _records(
    path: str | Path, namespace: str, keys: Sequence[str] | None, recover: bool
) -> list[Record]:
    """The recorded Zenoh messages of one file matching ``keys``, in file order."""
    wanted = _matcher(keys)
    recording = Recording(path)
    records = [
        r
        for r in recording
        if not r.topic.startswith("/") and wanted(r.topic.removeprefix(f"{namespace}/"))
    ]
    recording.check(recover)
    return records


def _recorder_metadata(path: str | Path) -> dict[str, str]:
    """What the recorder noted in ``path`` (namespace, part, start), if anything."""
    return read_metadata(path).get(ARMPLAN_METADATA, {})


def _check_order(files: list[Path], noted: list[dict[str, str]]) -> None:
    """Refuse files that are not the parts of recordings, once each, in order.

    Each part is stamped with the time it started (``started_ns``) and its
    number (``part``). Parts given out of order, parts of two recordings
    mixed, a file given twice or a part left out would play messages out of
    their order, twice, or with a hole.

    Raises:
        RecordingError: naming the files.
    """
    seen: dict[Path, Path] = {}
    for path in files:
        first = seen.setdefault(path.resolve(), path)
        if first is not path:
            raise RecordingError(f"{path} is given twice", path=str(path))
    for k in range(1, len(files)):
        before, now = noted[k - 1], noted[k]
        started = [int(n.get("started_ns", "-1")) for n in (before, now)]
        if min(started) >= 0 and started[1] <= started[0]:
            when = "at the same time as" if started[1] == started[0] else "before"
            raise RecordingError(
                f"{files[k]} was started {when} {files[k - 1]}: give the "
                "numbered files of one recording, in order",
                path=str(files[k]),
            )
        part, previous = int(now.get("part", "1")), int(before.get("part", "0"))
        if part > 1 and part != previous + 1:
            raise RecordingError(
                f"{files[k]} is part {part} of its recording but follows "
                f"{files[k - 1]}, part {previous}: part {previous + 1} is missing",
                path=str(files[k]),
            )


def _check_no_overlap(files: list[tuple[Path, list[Record]]]) -> None:
    """Refuse files whose messages were received while the one before's were.

    Consecutive parts of one recording follow each other (one writer wrote
    them, in order); two recordings made at the same time overlap, and would
    play their messages twice and out of order.

    Raises:
        RecordingError: naming the two files.
    """
    kept = [(path, records) for path, records in files if records]
    for (before, earlier), (path, later) in pairwise(kept):
        if later[0].publish_time < earlier[-1].publish_time:
            raise RecordingError(
                f"{path} overlaps {before}: its first message was received "
                f"{(earlier[-1].publish_time - later[0].publish_time) / 1e9:.3f} s "
                "before that file's last; two recordings made at once cannot be "
                "replayed as one",
                path=str(path),
            )


def replay_items(
    paths: str | Path | Sequence[str | Path],
    *,
    keys: Sequence[str] | None = None,
    recover: bool = False,
) -> list[ReplayItem]:
    """The recorded Zenoh messages to send again, in file order.

    Args:
        paths: An MCAP file written by the recorder, or the numbered files of
            a rotating recording, in order (offsets run on across them;
            files out of order, given twice or with a part missing between
            them are refused).
        keys: Only keys matching these expressions (relative to the
            namespace, e.g. ``plan/trajectory``, ``bridge/*``); all if ``None``.
        recover: Replay the readable prefix of a damaged file.

    Raises:
        RecordingError: if a file cannot be read (or is damaged, without
            ``recover``), or a raw payload in it is malformed.
    """
    files = [Path(paths)] if isinstance(paths, (str, Path)) else list(map(Path, paths))
    noted = [_recorder_metadata(path) for path in files]
    _check_order(files, noted)
    per_file = []
    for path, note in zip(files, noted, strict=True):
        namespace = note.get("namespace", "")
        per_file.append((path, namespace, _records(path, namespace, keys, recover)))
    _check_no_overlap([(path, records) for path, _, records in per_file])
    firsts = [records[0].log_time for _, _, records in per_file if records]
    if not firsts:
        return []
    items = []
    for path, namespace, records in per_file:
        try:
            items += [_item(r, namespace, firsts[0]) for r in records]
        except ValueError as exc:
            raise RecordingError(
                f"{path}: a raw payload cannot be decoded ({exc})", path=str(path)
            ) from None
    return items


def check_speed(speed: float, latest: float = 0.0) -> float:
    """``speed`` if it is a finite positive factor; else ``InvalidInputError``.

    Args:
        speed: The time scale.
        latest: The latest offset to send at [s]: ``latest / speed`` must be
            a wait a timer takes (under ``threading.TIMEOUT_MAX``, about 292
            years; a speed of 1e-300 asked for more and overflowed).
    """
    if not (math.isfinite(speed) and speed > 0):
        raise InvalidInputError(
            f"speed must be a positive number (1 = original timing), got {speed}",
            field="speed",
        )
    if latest / speed >= threading.TIMEOUT_MAX:
        raise InvalidInputError(
            f"speed {speed:g} is too small: the message at {latest:g} s would "
            f"be sent after {latest / speed:.3g} s, more than the longest wait "
            f"({threading.TIMEOUT_MAX:.3g} s)",
            field="speed",
        )
    return speed


def replay(
    items: Iterable[ReplayItem],
    publish: Publish,
    *,
    speed: float = 1.0,
    stop: threading.Event | None = None,
    clock: Callable[[], float] = time.monotonic,
) -> ReplayStats:
    """Send ``items`` at ``offset / speed`` seconds after the start.

    Args:
        items: The messages, in the order to send them.
        publish: Sends one: ``publish(relative key, payload, encoding)``.
        speed: Time scale: 2 plays twice as fast, 0.5 at half speed.
        stop: Set to end the replay early.
        clock: Monotonic time [s].

    Raises:
        InvalidInputError: if ``speed`` is not positive and finite.
    """
    check_speed(speed)
    stop = stop or threading.Event()
    start = clock()
    sent, late, last = 0, 0.0, start
    for item in items:
        check_speed(speed, item.offset)
        due = start + item.offset / speed
        if stop.wait(max(due - clock(), 0.0)):
            break
        last = clock()
        late = max(late, last - due)
        publish(item.path, item.payload, item.encoding)
        sent += 1
    return ReplayStats(sent, last - start, late)
