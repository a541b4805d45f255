"""What a recording holds, channel by channel: counts, time ranges, validity.

Unlike :func:`~shared.recording.reader.summarize` (one row per topic), a
channel here is a topic *and* its schema: the recorder may give a topic a
typed channel and a schemaless ``"json"`` one for payloads that did not parse.

A well-formed file is listed whole, whatever its messages: a channel of
another message encoding (a ROS 2 ``cdr`` one beside armplan's JSON) is
counted, its messages not read; so is a message that is not JSON.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from shared.recording.metadata import read_metadata
from shared.recording.reader import JSON, Record, Recording, which_message
from shared.recording.validation import check_record


@dataclass
class ChannelStats:
    """One channel of a recording.

    Attributes:
        topic: Its topic.
        schema: Its schema name ("" if none).
        count: Messages read.
        first: Earliest log time [ns since the epoch].
        last: Latest log time [ns since the epoch].
        invalid: Messages that do not match the schema (if checked).
        encoding: Its message encoding (``"json"``: armplan's).
        unread: Messages not read: all of a channel that is not JSON, and
            those that are not JSON.
    """

    topic: str
    schema: str
    count: int = 0
    first: int = 0
    last: int = 0
    invalid: int = 0
    encoding: str = JSON
    unread: int = 0

    @property
    def duration(self) -> float:
        """Time from the first to the last message [s]."""
        return (self.last - self.first) / 1e9

    @property
    def replayed(self) -> bool:
        """Whether ``armplan replay`` sends its messages: not a ``/...`` topic.

        A ``/...`` topic (the Foxglove channels the recorder derives, or
        another tool's) is no Zenoh key: replay sends none of it
        (``services.recorder.replay_parts.to_send``).
        """
        return not self.topic.startswith("/")


@dataclass
class Inventory:
    """What a recording holds.

    Attributes:
        path: The file.
        channels: Its channels, in order of first message; those the file
            declares without a message last (count 0).
        damage: What stopped the reading early (``None``: read whole).
        damage_code: Its kind, for programs (``Recording.damage_code``).
        metadata: Its metadata records by name.
        problems: The first few schema problems found (if checked).
        unread: The first few messages on JSON channels that are not JSON,
            each which and why (``message 3 of the file (...) is empty``).
        skew: The largest difference, log time minus publish (receipt)
            time, of a recorded message (not a derived ``/...`` one, whose
            log time is the moment it describes) [ns]; 0 if none.
        skew_topic: That message's topic ("" if none).
    """

    path: Path
    channels: list[ChannelStats] = field(default_factory=list)
    damage: str | None = None
    damage_code: str | None = None
    metadata: dict[str, dict[str, str]] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    unread: list[str] = field(default_factory=list)
    skew: int = 0
    skew_topic: str = ""

    @property
    def clock_offset(self) -> float | None:
        """``skew`` [s] if over ``CLOCK_OFFSET`` in size, else ``None``.

        A publisher's clock may be off by about that much.
        """
        return self.skew / 1e9 if abs(self.skew) > CLOCK_OFFSET * 1e9 else None

    def note_skew(self, record: Record) -> None:
        """Keep ``record``'s log minus publish time if the largest so far."""
        if record.topic.startswith("/") or not record.publish_time:
            return  # derived for Foxglove, or no publish time written
        skew = record.log_time - record.publish_time
        if abs(skew) > abs(self.skew):
            self.skew, self.skew_topic = skew, record.topic

    @property
    def count(self) -> int:
        """Messages read."""
        return sum(c.count for c in self.channels)

    @property
    def first(self) -> int | None:
        """Earliest log time [ns], ``None`` if there is no message."""
        return min((c.first for c in self.channels if c.count), default=None)

    @property
    def last(self) -> int | None:
        """Latest log time [ns], ``None`` if there is no message."""
        return max((c.last for c in self.channels if c.count), default=None)

    @property
    def foreign(self) -> list[ChannelStats]:
        """Its channels that are not JSON (their messages counted, not read)."""
        return [c for c in self.channels if c.encoding != JSON]


#: Schema problems (and messages not read) kept as examples in an inventory.
MAX_PROBLEMS = 10
#: Log and publish times further apart than this for some message make
#: ``inspect`` warn that a publisher's clock may be off [s].
CLOCK_OFFSET = 1.0


def take_inventory(
    path: str | Path, *, recover: bool = False, validate: bool = False
) -> Inventory:
    """Read every message of ``path`` and count it per channel.

    Messages it cannot read (a channel that is not JSON, a message that is
    not JSON) are counted as ``unread``, not damage.

    Args:
        path: An MCAP file.
        recover: On damage, keep what was read before it instead of raising.
        validate: Check each message against its channel's schema.

    Raises:
        RecordingError: if the file is missing, empty, not MCAP, or damaged
            (without ``recover``); it says how many messages were readable.
    """
    recording = Recording(path, keep_unread=True)
    inventory = Inventory(Path(path), metadata=read_metadata(path))
    channels: dict[tuple[str, str, str], ChannelStats] = {}
    for record in recording:
        key = (record.topic, record.schema, record.encoding)
        stats = channels.get(key)
        if stats is None:
            stats = channels[key] = ChannelStats(
                record.topic,
                record.schema,
                first=record.log_time,
                last=record.log_time,
                encoding=record.encoding,
            )
            inventory.channels.append(stats)
        stats.count += 1
        inventory.note_skew(record)
        stats.first = min(stats.first, record.log_time)
        stats.last = max(stats.last, record.log_time)
        if record.unread:
            stats.unread += 1
            if record.encoding == JSON and len(inventory.unread) < MAX_PROBLEMS:
                which = which_message(recording.count, record.topic, record.log_time)
                inventory.unread.append(f"{which} is {record.unread}")
        problem = check_record(record) if validate else None
        if problem is not None:
            stats.invalid += 1
            if len(inventory.problems) < MAX_PROBLEMS:
                inventory.problems.append(problem)
    recording.check(recover)
    for key in recording.channels:  # declared, but no message read on them
        if key not in channels:
            channels[key] = ChannelStats(key[0], key[1], encoding=key[2])
            inventory.channels.append(channels[key])
    inventory.damage = recording.damage
    inventory.damage_code = recording.damage_code
    return inventory
