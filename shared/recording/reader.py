"""Read armplan messages back from MCAP files: clear errors or a recovered prefix."""

from __future__ import annotations

import json
import struct
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, NamedTuple

from mcap.exceptions import EndOfFile, InvalidMagic, McapError
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import CRCValidationError, StreamReader

from shared.errors import RecordingError
from shared.printable import printable
from shared.recording.rotation import numbered_parts
from shared.text.counted import agreeing, counted

#: What each kind of damage means, for messages (``describe_damage``).
TRUNCATED = (
    "it ends in the middle of a record, without its summary (still being "
    "written, or its writer was stopped: killed, disk full)"
)
CHANGED = "its checksum does not match: bytes were changed after it was written"
NOT_JSON = "a message in it is not UTF-8 JSON"
NOT_MCAP = "it holds bytes that are not MCAP records"
NO_MAGIC = "no MCAP magic at its start"
NOT_UTF8 = (
    "a record in it other than a message (its header, a channel, a schema, "
    "metadata, a chunk or an index) holds text that is not UTF-8"
)
#: A stable name for each kind of damage (``Recording.damage_code``), for
#: programs: the words above may change, these do not.
DAMAGE_CODES = {
    TRUNCATED: "truncated",
    CHANGED: "changed",
    NOT_JSON: "not_json",
    NOT_MCAP: "not_mcap",
    NO_MAGIC: "no_magic",
    NOT_UTF8: "not_utf8",
}
#: The damage code of a well-formed file with a channel that is not JSON.
FOREIGN = "foreign"
#: The 8 bytes every MCAP file (version 0) starts with.
MAGIC = b"\x89MCAP0\r\n"
#: The message encoding of every armplan channel.
JSON = "json"


def _parts_hint(path: Path) -> str:
    """Where a rotated recording's numbered files are, if ``path`` was rotated."""
    parts = numbered_parts(path)
    if not parts:
        return ""
    names = parts[0].name if len(parts) == 1 else f"{parts[0].name} to {parts[-1].name}"
    return f"; the recording was rotated into {names}"


def describe_damage(error: Exception) -> str:
    """What a reading error says about the file, in words (no library names).

    ``error`` comes from reading the records, never a message's bytes (see
    ``Recording._record``): text that is not UTF-8 there is another
    record's (the header's profile or library, a channel's topic, a
    schema's name, metadata, a chunk's compression, an index's names), not
    a message's (it was said to be "a message in it is not UTF-8 JSON").
    """
    if isinstance(error, InvalidMagic):
        return NO_MAGIC
    if isinstance(error, CRCValidationError):
        return CHANGED
    if isinstance(error, (EndOfFile, struct.error)):
        return TRUNCATED
    if isinstance(error, UnicodeDecodeError):  # messages are decoded apart
        return NOT_UTF8
    return NOT_MCAP


class Record(NamedTuple):
    """One message of a recording.

    Attributes:
        topic: Channel topic.
        schema: Schema name (the message class), or "" if none.
        log_time: When the message was made [ns].
        publish_time: When it was received [ns].
        data: The decoded JSON message (``None`` if it was not read).
        raw: The message's bytes as recorded (its JSON, byte for byte).
        encoding: Its channel's message encoding (``"json"`` for armplan's).
        unread: Why it was not read (its channel is not JSON, or it is not
            JSON), ``""`` if it was; only with ``Recording(keep_unread=True)``.
    """

    topic: str
    schema: str
    log_time: int
    publish_time: int
    data: Any
    raw: bytes = b""
    encoding: str = JSON
    unread: str = ""


def which_message(number: int, topic: str, log_time: int) -> str:
    """A message in words: ``message 3 of the file (channel /a, log time 5 ns)``.

    Args:
        number: Its place in the file, from 1, among the messages of every topic.
        topic: Its channel's topic (made printable here).
        log_time: Its log time [ns].
    """
    where = f"channel {printable(topic)}, log time {log_time} ns"
    return f"message {number} of the file ({where})"


def _decode(data: bytes) -> tuple[Any, str]:
    """A message's JSON value and ``""``, or ``None`` and why it is not JSON."""
    if not data:
        return None, "empty (0 bytes)"
    try:
        return json.loads(data), ""
    except RecursionError:
        return None, "JSON nested too deeply to read"
    except UnicodeDecodeError:
        return None, "not UTF-8 text"
    except ValueError as exc:  # json.JSONDecodeError, and any other refusal
        return None, f"not JSON ({exc})"


class Recording:
    """The messages of one MCAP file, read in file order, stopping at damage.

    Iterate it for :class:`Record` s. Reading stops quietly at the first
    damaged byte (truncation by a killed writer, garbage, a checksum that
    does not match); afterwards ``damage`` says in words what was wrong
    (``None`` if the file was read whole), ``damage_code`` names its kind
    (a value of :data:`DAMAGE_CODES`, or :data:`FOREIGN`) and ``count`` how
    many messages came out. A message it cannot read as JSON, on a channel
    of another message encoding (``foreign``) or not JSON itself, stops the
    reading too, as damage naming the message; with ``keep_unread`` it comes
    out instead, its ``data`` ``None`` and its ``unread`` saying why, and
    the reading goes on (``armplan inspect`` lists a whole file so).

    Args:
        path: An MCAP file with JSON messages.
        topics: Only these topics (all if ``None``).
        keep_unread: Yield the messages it cannot read rather than stop.

    Raises:
        RecordingError: if the file is missing, a folder, empty or not MCAP
            (no MCAP magic at its start).
    """

    def __init__(
        self,
        path: str | Path,
        topics: Iterable[str] | None = None,
        *,
        keep_unread: bool = False,
    ) -> None:
        if not str(path):  # Path("") is ".", and "." is a folder
            raise RecordingError(
                "the recording's name is empty: name an MCAP file", path=""
            )
        self.path = Path(path)
        self.topics = None if topics is None else set(topics)
        self.keep_unread = keep_unread
        self.damage: str | None = None
        self.damage_code: str | None = None
        self.count = 0
        self.foreign: str | None = None
        self._schemas: dict[int, Schema] = {}
        self._channels: dict[int, Channel] = {}
        try:
            self._check_file()
        except OSError as exc:  # a name too long, a folder without permission
            raise RecordingError(
                f"cannot read {self.path}: {exc.strerror or exc}", path=str(self.path)
            ) from None

    def _check_file(self) -> None:
        """Refuse a path that is not a regular file starting as MCAP files do.

        Raises:
            RecordingError: naming what the path is instead.
            OSError: if the file system cannot even say (see ``__init__``).
        """
        if not self.path.exists():
            raise RecordingError(
                f"{self.path}: no such file{_parts_hint(self.path)}",
                path=str(self.path),
            )
        if self.path.is_dir():
            raise RecordingError(
                f"{self.path} is a folder, not an MCAP file", path=str(self.path)
            )
        if not self.path.is_file():
            raise RecordingError(
                f"{self.path} is not a regular file (a device or a pipe?), not an "
                "MCAP file",
                path=str(self.path),
                readable=0,
            )
        self._check_magic()

    def _check_magic(self) -> None:
        """Refuse a file that does not start with the MCAP magic, before reading.

        Nothing can be recovered from it, so it is an error even with
        ``recover``; a file shorter than the magic is no MCAP file cut short
        but one in which nothing was recorded.

        Raises:
            RecordingError: the file is empty, ends inside the magic (its
                writer stopped at its first bytes), or starts otherwise.
        """
        with open(self.path, "rb") as stream:
            head = stream.read(len(MAGIC))
        if head == MAGIC:
            return
        if not head:
            why = "is empty (0 bytes), not an MCAP file: nothing was recorded in it"
        elif MAGIC.startswith(head):
            why = (
                f"ends inside the MCAP magic ({len(head)} of its {len(MAGIC)} "
                "bytes), not an MCAP file: nothing was recorded in it (its "
                "writer stopped at its first bytes)"
            )
        else:
            why = f"is not an MCAP file ({NO_MAGIC})"
        raise RecordingError(f"{self.path} {why}", path=str(self.path), readable=0)

    @property
    def channels(self) -> list[tuple[str, str, str]]:
        """Every channel read so far, messages or not, as the file declares them.

        Each as (topic, schema name or "", message encoding).
        """
        return [
            (c.topic, self._schema_name(c.schema_id), c.message_encoding)
            for c in self._channels.values()
        ]

    def _schema_name(self, schema_id: int) -> str:
        schema = self._schemas.get(schema_id)
        return schema.name if schema is not None else ""

    def _messages(self, stream: Any) -> Iterator[tuple[Channel, Message]]:
        """Each message with its channel, the schemas and channels kept."""
        self._schemas, self._channels = {}, {}
        for record in StreamReader(stream, validate_crcs=True).records:
            if isinstance(record, Schema):
                self._schemas[record.id] = record
            elif isinstance(record, Channel):
                if record.schema_id and record.schema_id not in self._schemas:
                    raise McapError(f"no schema with id {record.schema_id}")
                self._channels.setdefault(record.id, record)
            elif isinstance(record, Message):
                channel = self._channels.get(record.channel_id)
                if channel is None:
                    raise McapError(f"no channel with id {record.channel_id}")
                yield channel, record

    def __iter__(self) -> Iterator[Record]:
        self.damage, self.damage_code = None, None
        self.count, self.foreign = 0, None
        try:
            stream = open(self.path, "rb")  # noqa: SIM115 (closed below)
        except OSError as exc:
            raise RecordingError(
                f"cannot read {self.path}: {exc.strerror}", path=str(self.path)
            ) from None
        with stream:
            messages = self._messages(stream)
            number = 0  # messages of the file so far, of every topic
            while True:
                try:
                    channel, message = next(messages)
                except StopIteration:
                    return
                except Exception as exc:  # any failure to read the records is damage
                    self.damage = describe_damage(exc)
                    self.damage_code = DAMAGE_CODES[self.damage]
                    return
                number += 1
                record = self._record(channel, message, number)
                if record.unread and not self.keep_unread:
                    return
                if self.topics is not None and channel.topic not in self.topics:
                    continue
                self.count += 1
                yield record

    def _record(self, channel: Channel, message: Message, number: int) -> Record:
        """Message ``number`` of the file, read if it can be.

        One that cannot is ``unread``; it also sets ``foreign`` (its channel
        is not JSON, the first such channel) or, unless ``keep_unread``,
        ``damage`` (it stops the reading).
        """
        encoding = channel.message_encoding
        if encoding != JSON:
            data = None
            unread = f"message encoding {printable(encoding) or '(none)'}, not {JSON}"
            if self.foreign is None:
                self.foreign = f"channel {printable(channel.topic)} has {unread}"
            if not self.keep_unread:
                self.damage, self.damage_code = self.foreign, FOREIGN
        else:
            data, unread = _decode(message.data)
            if unread and not self.keep_unread:
                self.damage_code = DAMAGE_CODES[NOT_JSON]
                which = which_message(number, channel.topic, message.log_time)
                self.damage = f"{NOT_JSON}: {which} is {unread}"
        return Record(
            channel.topic,
            self._schema_name(channel.schema_id),
            message.log_time,
            message.publish_time,
            data,
            message.data,
            encoding,
            unread,
        )

    def check(self, recover: bool) -> None:
        """After reading: raise if damaged (unless ``recover``) or not MCAP at all.

        Raises:
            RecordingError: :meth:`error`, if the file was damaged and
                ``recover`` is False, or if nothing in it was MCAP (even with
                ``recover``: there is no prefix to recover).
        """
        if self.damage is None:
            return
        if not recover or self.not_mcap or self.refused:
            raise self.error()

    @property
    def refused(self) -> bool:
        """Whether the reading stopped at a channel that is not JSON (``foreign``)."""
        return self.damage_code == FOREIGN

    @property
    def not_mcap(self) -> bool:
        """Whether nothing in the file was MCAP (no magic at its start)."""
        return self.count == 0 and self.damage == NO_MAGIC

    def error(self) -> RecordingError:
        """The error that describes this file's damage."""
        if self.refused:  # well-formed, but not ours: not damage
            return RecordingError(
                f"{self.path} is not an armplan recording: {self.foreign} "
                "(armplan records JSON messages)",
                path=str(self.path),
                readable=self.count,
            )
        if self.not_mcap:
            return RecordingError(
                f"{self.path} is not an MCAP file ({NO_MAGIC})",
                path=str(self.path),
                readable=0,
            )
        if self.damage == CHANGED:  # found at the end: which message, unknown
            return RecordingError(
                f"{self.path}: {CHANGED}, somewhere in its "
                f"{counted(self.count, 'message')} "
                "(which cannot be told); --recover (or recover=True) reads them "
                "all, the changed bytes included",
                path=str(self.path),
                readable=self.count,
            )
        return RecordingError(
            f"{self.path} is damaged after {self.count} readable "
            f"{agreeing(self.count, 'message')}: {self.damage}; --recover (or "
            f"recover=True) reads {agreeing(self.count, 'that', 'those')} "
            f"{agreeing(self.count, 'message')}",
            path=str(self.path),
            readable=self.count,
        )


def read_records(
    path: str | Path, *, topics: Iterable[str] | None = None, recover: bool = False
) -> Iterator[Record]:
    """The messages of ``path`` in file order.

    Args:
        path: An MCAP file written by armplan (or any JSON-encoded MCAP).
        topics: Only these topics (all if ``None``).
        recover: On damage, stop at the last readable message instead of raising.

    Raises:
        RecordingError: if the file is missing, empty, not MCAP, or (without
            ``recover``) damaged; the error says how many messages were
            readable before the damage.
    """
    recording = Recording(path, topics)
    yield from recording
    recording.check(recover)


class Summary(NamedTuple):
    """What a recording holds.

    Attributes:
        channels: Per topic: (schema name, message count, first and last log time [ns]).
        damage: What stopped the reading early, or ``None`` if the file is whole.
    """

    channels: dict[str, tuple[str, int, int, int]]
    damage: str | None


def summarize(path: str | Path, *, recover: bool = False) -> Summary:
    """Channels, counts and time ranges of ``path`` (reads every message).

    Raises:
        RecordingError: if the file is damaged and ``recover`` is False.
    """
    recording = Recording(path)
    channels: dict[str, tuple[str, int, int, int]] = {}
    for r in recording:
        schema, n, first, last = channels.get(
            r.topic, (r.schema, 0, r.log_time, r.log_time)
        )
        channels[r.topic] = (
            schema,
            n + 1,
            min(first, r.log_time),
            max(last, r.log_time),
        )
    recording.check(recover)
    return Summary(channels, recording.damage)
