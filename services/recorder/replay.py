"""A recording's messages, sent again with their original timing, scaled.

:func:`replay_items` gives the recorded Zenoh messages of files (not the
derived ``/...`` Foxglove channels) in file order, which is the order the
recorder received them, with each one's offset from the first [s], its
original bytes (a ``RawPayload`` is unwrapped) and its Zenoh encoding.

Offsets keep the spacing the messages had as they crossed the bus, in file
order, and never decrease. In files armplan's recorder wrote they come from
the publish times, which are the recorder's receipt times (its clock alone,
written in file order). Not from the log times: those are Zenoh timestamps,
the publisher's own clock when it sets one, and a message stamped by a
publisher whose clock was 20 s behind held a replay of a 0.5 s session
for 21.6 s. In a file another tool wrote the offsets come from the log
times, each at least the one before (a file in reverse log-time order
goes out at once, in file order). Keys are made relative to the recorded namespace, so a
replay may publish under another one (a file another tool wrote notes
none: its topics under the replay's namespace are full keys in it). The
files are checked whole first (``replay_parts``), then read again message
by message as they are sent: the messages are never all in memory.
:func:`replay` sends them through a ``publish`` function at ``offset /
speed`` after the start; the caller supplies the Zenoh put.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import NamedTuple

from services.recorder.replay_parts import (
    Part,
    check_damage,
    check_no_overlap,
    check_order,
    look_through,
    matcher,
    to_send,
)
from shared.bus.config import DEFAULT_NAMESPACE
from shared.errors import InvalidInputError, RecordingError
from shared.recording.raw_payload import ZENOH_ENCODING, RawPayload
from shared.recording.survey import Stamp, Survey
from shared.text.counted import counted

#: Encoding of the JSON messages of a recording that did not note theirs
#: (made before the recorder noted it in the channel's metadata).
JSON_ENCODING = "application/json"
_NS_PER_S = 1e9

Publish = Callable[[str, bytes, str], None]


class ReplayItem(NamedTuple):
    """One message to send again.

    Attributes:
        offset: When to send it after the first message [s]: its receipt
            (else log) time minus the first's, at least the one before's.
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
        duration: Wall time from the start to the last send, or to the
            stop of a replay stopped early [s] (one stopped after its first
            message said "sent 1 of 2 messages in 0.000 s" after seconds).
        late: Largest delay of a send behind its scheduled time [s] (a
            send on time or early counts 0).
    """

    sent: int
    duration: float
    late: float


def _item(part: Part, stamp: Stamp, first: int, by_receipt: bool) -> ReplayItem:
    """The message of ``stamp`` (its bytes read) to send again.

    Its offset is not yet made at least the one before's (``Replay``).

    Raises:
        RecordingError: if it is a ``RawPayload`` that cannot be decoded.
    """
    path = part.topics[stamp.channel.topic]
    when = stamp.publish_time if by_receipt else stamp.log_time
    offset = (when - first) / _NS_PER_S
    data = stamp.data or b""
    if stamp.schema != RawPayload.__name__:
        encoding = stamp.channel.metadata.get(ZENOH_ENCODING, JSON_ENCODING)
        return ReplayItem(offset, path, data, encoding)
    try:
        raw = RawPayload.model_validate_json(data)
        return ReplayItem(offset, path, raw.payload(), raw.encoding)
    except ValueError as exc:
        raise RecordingError(
            f"{part.path}: a raw payload cannot be decoded ({exc})",
            path=str(part.path),
        ) from None


def _read(part: Part, first: int, by_receipt: bool) -> Iterator[ReplayItem]:
    """The messages of ``part`` to send, read one at a time.

    Raises:
        RecordingError: if a raw payload cannot be decoded, or the file no
            longer holds what the look through it found (changed since).
    """
    if not part.count:
        return
    read = 0
    for stamp in Survey(part.path, read=part.topics, only=part.topics, verify=False):
        yield _item(part, stamp, first, by_receipt)
        read += 1
        if read == part.count:
            return
    if not part.damaged:  # a damaged file's prefix may read shorter here
        raise RecordingError(
            f"{part.path} changed while it was replayed: {read} of its "
            f"{counted(part.count, 'message')} to send could be read again",
            path=str(part.path),
            readable=read,
        )


class Replay:
    """The messages of a recording to send again, counted, read as they go.

    Iterate it for :class:`ReplayItem` s in file order; ``len`` is how many.

    Args:
        parts: Each file's messages to send, in order.
        by_receipt: Time them by their publish (receipt) times, which
            armplan's recorder writes in file order; else by their log times.

    Attributes:
        first: The time the offsets count from [ns]: the first message's.
    """

    def __init__(self, parts: list[Part], by_receipt: bool = False) -> None:
        self.parts = parts
        self.by_receipt = by_receipt
        self.count = sum(part.count for part in parts)
        firsts = [part.first for part in parts if part.count]
        span = firsts[0] if firsts else None
        if span is None:
            self.first = 0
        else:
            self.first = span.first_publish if by_receipt else span.first_log

    def __len__(self) -> int:
        return self.count

    def __iter__(self) -> Iterator[ReplayItem]:
        latest = 0.0
        for part in self.parts:
            for item in _read(part, self.first, self.by_receipt):
                latest = max(latest, item.offset)
                yield item._replace(offset=latest)

    @property
    def latest(self) -> float:
        """The latest offset of a message to send [s] (0 if none)."""
        spans = [part.spans[topic] for part in self.parts for topic in part.topics]
        latest = [
            max(s.first_publish, s.last_publish) if self.by_receipt else s.latest_log
            for s in spans
        ]
        return max((max(latest) - self.first) / _NS_PER_S, 0.0) if latest else 0.0

    @property
    def counts(self) -> dict[str, int]:
        """Messages to send per relative key, in order of first message."""
        counts: dict[str, int] = {}
        for part in self.parts:
            for topic, path in part.topics.items():
                counts[path] = counts.get(path, 0) + part.spans[topic].count
        return counts

    @property
    def namespaces(self) -> set[str]:
        """The namespaces the files were recorded in (as armplan's recorder noted)."""
        return {part.namespace for part in self.parts if part.namespace is not None}

    @property
    def recorded(self) -> list[str]:
        """Every relative key recorded in the files, sent or not, sorted."""
        return sorted(set().union(*(part.recorded for part in self.parts)))


def replay_items(
    paths: str | Path | Sequence[str | Path],
    *,
    keys: Sequence[str] | None = None,
    recover: bool = False,
    namespace: str = DEFAULT_NAMESPACE,
) -> Replay:
    """The recorded Zenoh messages to send again, in file order.

    Everything that can be refused is refused here, before the first
    message is read for sending; the messages are read as the result is
    iterated (a malformed raw payload, which only another writer than
    armplan's records, is found there).

    Args:
        paths: An MCAP file written by the recorder, or the numbered files of
            a rotating recording, in order (offsets run on across them;
            files out of order, given twice or with a part missing between
            them are refused).
        keys: Only keys matching these expressions (relative to the
            namespace, e.g. ``plan/trajectory``, ``bridge/*``); all if ``None``.
        recover: Replay the readable prefix of a damaged file.
        namespace: The namespace the messages go out under: in a file
            without the recorder's namespace (another tool's), a topic
            already under it is taken as a full key, not moved under it
            again (``replay_parts.relative_key``).

    Raises:
        InvalidInputError: if a key is not a Zenoh key expression.
        RecordingError: if a file cannot be read (or is damaged, without
            ``recover``), its armplan metadata is malformed, a recorded key
            is not a Zenoh key (and ``keys`` do not leave it out), or the
            files are not the parts of one recording in order.
    """
    files = [Path(paths)] if isinstance(paths, (str, Path)) else list(map(Path, paths))
    wanted = matcher(keys)
    looked = [look_through(path) for path in files]
    check_order(looked)
    for each in looked:
        check_damage(each, recover)
    parts = [to_send(each, wanted, bool(keys), namespace) for each in looked]
    check_no_overlap(parts)
    by_receipt = all(each.noted for each in looked)  # armplan's recorder wrote them
    return Replay(parts, by_receipt)


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
            last = clock()  # the time it ran, not its last send's
            break
        last = clock()
        late = max(late, last - due)
        publish(item.path, item.payload, item.encoding)
        sent += 1
    return ReplayStats(sent, last - start, late)
