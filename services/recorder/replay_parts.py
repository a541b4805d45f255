"""The files of a replay, looked through before its first message is sent.

A replay refuses, before sending anything, files that are damaged (unless
``recover``), parts of a rotated recording given out of order, twice or with
one left out, two recordings made at once, and recorded keys that are not
Zenoh keys; it counts what it will send and when the last message goes.
None of that needs a message's bytes: :func:`look_through` makes one quick
pass over each file (``shared.recording.survey``) and keeps, per topic, a
count and where its first and last messages are, in memory that does not
grow with the recording. The messages are read again as they are sent.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from functools import cache
from itertools import pairwise
from pathlib import Path

import zenoh

from services.recorder.routing import ASKED
from shared.errors import InvalidInputError, RecordingError
from shared.recording.metadata import ARMPLAN_METADATA
from shared.recording.reader import Recording
from shared.recording.survey import Survey

Matcher = Callable[[str], bool]


@dataclass(slots=True)
class TopicSpan:
    """One topic's messages in a file.

    Attributes:
        count: How many.
        first: File position (0, 1, ...) of its first message among all.
        first_log: That message's log time [ns].
        first_publish: Its publish time [ns].
        last: File position of its last message.
        last_publish: That message's publish time [ns].
        latest_log: The latest log time of any of its messages [ns].
    """

    count: int
    first: int
    first_log: int
    first_publish: int
    last: int
    last_publish: int
    latest_log: int


def spans(messages: Iterable[tuple[str, int, int]]) -> dict[str, TopicSpan]:
    """Each topic's span, from (topic, log time, publish time) in file order."""
    found: dict[str, TopicSpan] = {}
    for index, (topic, log_time, publish_time) in enumerate(messages):
        span = found.get(topic)
        if span is None:
            found[topic] = TopicSpan(
                1, index, log_time, publish_time, index, publish_time, log_time
            )
            continue
        span.count += 1
        span.last, span.last_publish = index, publish_time
        span.latest_log = max(span.latest_log, log_time)
    return found


@dataclass(frozen=True)
class Looked:
    """One file after the quick pass.

    Attributes:
        path: The file.
        noted: What the recorder noted in it (namespace, part, start).
        spans: Its topics' spans (of its readable prefix, if not whole).
        damaged: The file read as ``Recording`` reads it, if the quick pass
            found it not whole (``None``: whole); it says what is wrong.
    """

    path: Path
    noted: dict[str, str]
    spans: dict[str, TopicSpan]
    damaged: Recording | None


def look_through(path: Path) -> Looked:
    """The quick pass over ``path`` (see the module docstring).

    A file the pass finds not whole is read again as ``Recording`` reads it,
    message by message without keeping them, to say what is wrong; the
    spans then cover what that reading read.
    """
    survey = Survey(path)
    found = spans((s.channel.topic, s.log_time, s.publish_time) for s in survey)
    noted = survey.metadata.get(ARMPLAN_METADATA, {})
    if survey.clean:
        return Looked(path, noted, found, None)
    recording = Recording(path)
    found = spans((r.topic, r.log_time, r.publish_time) for r in recording)
    return Looked(path, noted, found, recording)


def check_damage(looked: Looked, recover: bool) -> None:
    """Refuse a damaged file (with ``recover``: one not MCAP, or not JSON).

    Raises:
        RecordingError: ``Recording``'s error for it.
    """
    recording = looked.damaged
    if recording is None:
        return
    if recording.damage is None:  # whole to Recording, not to the quick pass
        raise RecordingError(
            f"{looked.path} cannot be read record by record for a replay",
            path=str(looked.path),
        )
    recording.check(recover)


@cache
def is_key(path: str) -> bool:
    """Whether ``path`` is a Zenoh key, relative (``plan/trajectory``).

    A key expression with a wildcard (``*/trajectory``, ``**``, ``a$*``) is
    not one: a put on it reaches every subscriber of a key it matches (a
    bridge's ``plan/trajectory`` included), past the live-bridge check,
    which reads the key's first chunk.
    """
    try:
        zenoh.KeyExpr(f"r/{path}")
    except zenoh.ZError:
        return False
    return "*" not in path  # in a valid key expression, '*' is a wildcard


def matcher(keys: Sequence[str] | None) -> Matcher:
    """Whether a relative key matches one of ``keys`` (all if ``None``).

    Raises:
        InvalidInputError: if a key is not a Zenoh key expression.
    """
    if not keys:
        return lambda path: True
    try:
        exprs = [zenoh.KeyExpr(f"r/{key}") for key in keys]
    except zenoh.ZError:
        raise InvalidInputError(
            f"--keys {' '.join(keys)}: not Zenoh key expressions", field="keys"
        ) from None
    return lambda path: is_key(path) and any(e.intersects(f"r/{path}") for e in exprs)


@dataclass(frozen=True)
class Part:
    """One file's messages to send.

    Attributes:
        path: The file.
        topics: Channel topic -> relative key, for each topic to send, in
            order of first message.
        spans: Every topic's span (the derived ``/...`` ones too).
        recorded: Every recorded relative key (sent or not).
        damaged: Whether it is read up to damage (``recover``).
        namespace: The namespace armplan's recorder noted in it (``None``
            in another tool's file).
        damage: With ``recover``, what is wrong with a damaged file, in
            words; ``None`` if it is whole.
        readable: Its messages (every channel) before the damage.
    """

    path: Path
    topics: dict[str, str]
    spans: dict[str, TopicSpan]
    recorded: frozenset[str]
    damaged: bool
    namespace: str | None = None
    damage: str | None = None
    readable: int = 0

    @property
    def count(self) -> int:
        """Messages to send."""
        return sum(self.spans[topic].count for topic in self.topics)

    @property
    def first(self) -> TopicSpan | None:
        """The span of the topic whose message is sent first."""
        return min(
            (self.spans[t] for t in self.topics), key=lambda s: s.first, default=None
        )

    @property
    def last(self) -> TopicSpan | None:
        """The span of the topic whose message is sent last."""
        return max(
            (self.spans[t] for t in self.topics), key=lambda s: s.last, default=None
        )


def relative_key(topic: str, recorded: str | None, namespace: str) -> str:
    """``topic``'s key relative to the namespace (the replay puts it under its own).

    Armplan's recorder notes the namespace it recorded (``recorded``), and
    its topics are full keys under it: ``armplan/plan/trajectory`` gives
    ``plan/trajectory``. A file another tool wrote notes none: a topic under
    the replay's ``namespace`` is a full key in it, published unchanged
    (``armplan/plan/trajectory`` went out as ``armplan/armplan/plan/...``);
    any other topic is taken as relative (``plan/trajectory``).
    """
    return topic.removeprefix(f"{recorded or namespace}/")


def to_send(looked: Looked, wanted: Matcher, keys_given: bool, namespace: str) -> Part:
    """What of ``looked`` to send: its recorded keys that ``wanted`` matches.

    Args:
        looked: The file.
        wanted: Whether a relative key is to be sent.
        keys_given: Whether ``--keys`` chose the keys.
        namespace: The replay's namespace (see :func:`relative_key`).

    Raises:
        RecordingError: if a recorded key is not a Zenoh key and no
            ``--keys`` leave it out.
    """
    recorded = looked.noted.get("namespace")
    relative = {
        topic: relative_key(topic, recorded, namespace)
        for topic, _ in sorted(looked.spans.items(), key=lambda item: item[1].first)
        if not topic.startswith("/")  # derived for Foxglove: not sent
    }
    # the recorder's own questions' answers (the model at its start): no
    # service publishes them, and a put on a queryable's key reaches no one
    relative = {t: path for t, path in relative.items() if path not in ASKED}
    bad = [topic for topic, path in relative.items() if not is_key(path)]
    if bad and not keys_given:
        span = looked.spans[bad[0]]
        raise RecordingError(
            f"{looked.path}: its channel {bad[0]!r} is not a Zenoh key (no '#' "
            "or '?', no wildcard '*', which a put sends to every key it "
            "matches, no empty chunk, no '/' at either end), so its "
            f"{span.count} message{'' if span.count == 1 else 's'} cannot be "
            "sent again; --keys can choose the other keys",
            path=str(looked.path),
        )
    return Part(
        looked.path,
        {topic: path for topic, path in relative.items() if wanted(path)},
        looked.spans,
        frozenset(relative.values()),
        looked.damaged is not None,
        recorded,
        None if looked.damaged is None else looked.damaged.damage,
        0 if looked.damaged is None else looked.damaged.count,
    )


def _noted_number(path: Path, noted: dict[str, str], name: str) -> int | None:
    """The whole number the recorder noted as ``name`` in ``path``, if any.

    Raises:
        RecordingError: if it is not one (a damaged or foreign file).
    """
    value = noted.get(name)
    if value is None:
        return None
    if not (value.isascii() and value.isdigit()):
        raise RecordingError(
            f"{path}: its armplan metadata gives {name} {value!r}, not a whole "
            "number (the file is damaged or was not written by armplan's "
            "recorder)",
            path=str(path),
        )
    return int(value)


def check_order(looked: list[Looked]) -> None:
    """Refuse files that are not the parts of recordings, once each, in order.

    Each part is stamped with the time it started (``started_ns``), its
    number (``part``) and, since the recorder noted it, the time its
    recording's part 1 started (``recording_ns``). Parts given out of order,
    parts of two recordings mixed, a file given twice or a part left out
    would play messages out of their order, twice, or with a hole. A part
    after the first follows the part before it of its own recording; part 1
    (a recording that does not rotate, too) may follow any file.

    Raises:
        RecordingError: naming the files, or a file whose stamps are not
            whole numbers.
    """
    seen: dict[Path, Path] = {}
    for each in looked:
        first = seen.setdefault(each.path.resolve(), each.path)
        if first is not each.path:
            raise RecordingError(f"{each.path} is given twice", path=str(each.path))
    started = [_noted_number(each.path, each.noted, "started_ns") for each in looked]
    parts = [_noted_number(each.path, each.noted, "part") for each in looked]
    recordings = [
        _noted_number(each.path, each.noted, "recording_ns") for each in looked
    ]
    for k in range(1, len(looked)):
        before, now = looked[k - 1].path, looked[k].path
        was, is_ = started[k - 1], started[k]
        if was is not None and is_ is not None and is_ <= was:
            when = "at the same time as" if is_ == was else "before"
            raise RecordingError(
                f"{now} was started {when} {before}: give the "
                "numbered files of one recording, in order",
                path=str(now),
            )
        part, previous = parts[k] or 1, parts[k - 1] or 0
        ours, theirs = recordings[k], recordings[k - 1]
        if part > 1 and ours is not None and theirs is not None and ours != theirs:
            raise RecordingError(
                f"{now} is part {part} of another recording than {before} "
                f"(its part {previous}): give the numbered files of one "
                "recording, in order",
                path=str(now),
            )
        if part > 1 and part <= previous:
            raise RecordingError(
                f"{now} is part {part} of its recording but follows {before}, "
                f"part {previous}, started before it: they are not of one "
                "recording; give the numbered files of one recording, in order",
                path=str(now),
            )
        if part > 1 and part != previous + 1:
            raise RecordingError(
                f"{now} is part {part} of its recording but follows "
                f"{before}, part {previous}: part {previous + 1} is missing",
                path=str(now),
            )


def check_no_overlap(parts: list[Part]) -> None:
    """Refuse files whose messages were received while the one before's were.

    Consecutive parts of one recording follow each other (one writer wrote
    them, in order); two recordings made at the same time overlap, and would
    play their messages twice and out of order.

    Raises:
        RecordingError: naming the two files.
    """
    kept = [each for each in parts if each.count]
    for before, now in pairwise(kept):
        last, first = before.last, now.first
        assert last is not None and first is not None
        if first.first_publish < last.last_publish:
            raise RecordingError(
                f"{now.path} overlaps {before.path}: its first message was "
                f"received {(last.last_publish - first.first_publish) / 1e9:.3f} s "
                "before that file's last; two recordings made at once cannot be "
                "replayed as one",
                path=str(now.path),
            )
