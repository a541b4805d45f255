"""A quick pass over an MCAP file: its metadata, channels and message times.

Reading a recording with :class:`~shared.recording.reader.Recording` parses
every record, message bytes included, and checks the data's checksum as it
goes: 3.3 s for a 200 MB file, before any JSON is parsed. A replay must look
at a recording whole before it sends the first message (are the parts in
order, do the keys match anything, is the file whole) but needs no
message's bytes for that. :class:`Survey` reads each record's header, reads
the small records (metadata, schemas, channels) whole, skips the bytes of
the messages it is not asked for, and checks the data's checksum in 64 KiB
blocks: 0.3 s for the same file, in memory that does not grow with it.

A survey only says whether the file is whole (``clean``). What is wrong
with one that is not is for ``Recording`` to say, in the words every
command uses (``Recording.error``).
"""

from __future__ import annotations

import os
import struct
import zlib
from collections.abc import Collection, Iterator
from io import BytesIO
from pathlib import Path
from typing import IO, NamedTuple

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import Channel, Chunk, DataEnd, Message, Metadata, Schema
from mcap.stream_reader import breakup_chunk

from shared.errors import RecordingError
from shared.recording.reader import JSON, Recording

MAGIC = b"\x89MCAP0\r\n"
#: A record's opcode and body length [bytes].
_RECORD = struct.Struct("<BQ")
#: A message's channel id, sequence, log time and publish time [ns].
_MESSAGE = struct.Struct("<HIQQ")
#: The longest record read whole [bytes] (the ``mcap`` stream reader's limit).
RECORD_LIMIT = 4 * 2**30
#: The opcode of a message record, as a plain int (compared for every record).
_MESSAGE_OPCODE = int(Opcode.MESSAGE)
#: Bytes checksummed at a time [bytes].
_BLOCK = 2**16


class Stamp(NamedTuple):
    """One message, as a survey sees it.

    Attributes:
        channel: Its channel (topic, message encoding, metadata).
        schema: Its channel's schema name, or "" if none.
        log_time: When it was made [ns].
        publish_time: When it was received [ns].
        data: Its bytes, if its topic was asked for (else ``None``).
    """

    channel: Channel
    schema: str
    log_time: int
    publish_time: int
    data: bytes | None


class _NotWholeError(Exception):
    """The file is not whole from here on (``Survey.clean`` stays False)."""


class Survey:
    """The messages of one MCAP file in file order, their bytes mostly skipped.

    Iterate it for :class:`Stamp` s. Iteration stops quietly where the file
    stops being whole MCAP with JSON messages (what ``Recording`` would call
    damage or a foreign file); afterwards ``clean`` says whether it read the
    whole file, summary and checksum included, and ``metadata`` holds the
    metadata records read.

    Args:
        path: An MCAP file.
        read: Topics whose messages' bytes to read (``Stamp.data``).
        only: Yield only the messages of these topics (all if ``None``).
        verify: Check the data section's checksum at the end.

    Raises:
        RecordingError: if the file is missing, a folder, empty or unreadable.
    """

    def __init__(
        self,
        path: str | Path,
        *,
        read: Collection[str] = (),
        only: Collection[str] | None = None,
        verify: bool = True,
    ) -> None:
        Recording(path)  # the same checks and errors as for reading messages
        self.path = Path(path)
        self.read = read
        self.only = only
        self.verify = verify
        self.clean = False
        self.metadata: dict[str, dict[str, str]] = {}
        self._schemas: dict[int, str] = {}
        self._channels: dict[int, Channel] = {}

    def __iter__(self) -> Iterator[Stamp]:
        self.clean, self.metadata = False, {}
        self._schemas, self._channels = {}, {}
        try:
            stream = open(self.path, "rb")  # noqa: SIM115 (closed below)
        except OSError as exc:
            raise RecordingError(
                f"cannot read {self.path}: {exc.strerror}", path=str(self.path)
            ) from None
        with stream:
            size = os.fstat(stream.fileno()).st_size
            try:
                yield from self._records(stream, size)
            except Exception:  # any failure to read the bytes: not whole
                return

    def _records(self, stream: IO[bytes], size: int) -> Iterator[Stamp]:
        """Every message up to the footer; then sets ``clean``."""
        if stream.read(len(MAGIC)) != MAGIC:
            raise _NotWholeError
        checksum: tuple[int, int] | None = None  # (end of the data, its CRC)
        end = len(MAGIC)  # kept, not asked of the stream (tell() is slow)
        while True:
            start = end
            head = stream.read(_RECORD.size)
            if len(head) < _RECORD.size:
                raise _NotWholeError
            opcode, length = _RECORD.unpack(head)
            end = start + _RECORD.size + length
            if length > RECORD_LIMIT or end > size:
                raise _NotWholeError
            if opcode == _MESSAGE_OPCODE:
                stamp = self._message(stream, length)
                if stamp is not None:
                    yield stamp
            elif opcode == Opcode.CHUNK:
                yield from self._chunk(stream.read(length))
            elif opcode == Opcode.FOOTER:
                stream.seek(end)
                if stream.read(len(MAGIC)) != MAGIC:
                    raise _NotWholeError
                self.clean = checksum is None or self._checksum_right(stream, *checksum)
                return
            elif opcode == Opcode.DATA_END:
                crc = DataEnd.read(_body(stream, length)).data_section_crc
                checksum = (start, crc) if crc else None
            elif opcode in (Opcode.SCHEMA, Opcode.CHANNEL, Opcode.METADATA):
                self._small(opcode, _body(stream, length))
            stream.seek(end)

    def _small(self, opcode: int, body: ReadDataStream) -> None:
        """Keep a schema's name, a channel, or a metadata record."""
        if opcode == Opcode.SCHEMA:
            schema = Schema.read(body)
            self._schemas[schema.id] = schema.name
        elif opcode == Opcode.CHANNEL:
            self._channel(Channel.read(body))
        else:
            metadata = Metadata.read(body)
            self.metadata[metadata.name] = dict(metadata.metadata)

    def _channel(self, channel: Channel) -> None:
        if channel.schema_id and channel.schema_id not in self._schemas:
            raise _NotWholeError  # a channel of no schema
        self._channels.setdefault(channel.id, channel)

    def _message(self, stream: IO[bytes], length: int) -> Stamp | None:
        """The stamp of the message record at ``stream`` (its header read)."""
        if length < _MESSAGE.size:
            raise _NotWholeError
        channel_id, _, log_time, publish_time = _MESSAGE.unpack(
            stream.read(_MESSAGE.size)
        )
        channel = self._channel_of(channel_id)
        if self.only is not None and channel.topic not in self.only:
            return None
        data = None
        if channel.topic in self.read:
            data = stream.read(length - _MESSAGE.size)
        schema = self._schemas.get(channel.schema_id, "")
        return Stamp(channel, schema, log_time, publish_time, data)

    def _channel_of(self, channel_id: int) -> Channel:
        """The channel of a message; it must be declared and JSON.

        A file with a message that is not JSON is not whole here (a foreign
        file, in ``Recording``'s words).
        """
        channel = self._channels.get(channel_id)
        if channel is None or channel.message_encoding != JSON:
            raise _NotWholeError
        return channel

    def _chunk(self, body: bytes) -> Iterator[Stamp]:
        """The messages of a chunk (decompressed whole: one chunk at a time)."""
        chunk = Chunk.read(ReadDataStream(BytesIO(body)))
        for record in breakup_chunk(chunk, validate_crc=self.verify):
            if isinstance(record, Schema):
                self._schemas[record.id] = record.name
            elif isinstance(record, Channel):
                self._channel(record)
            elif isinstance(record, Message):
                channel = self._channel_of(record.channel_id)
                if self.only is not None and channel.topic not in self.only:
                    continue
                yield Stamp(
                    channel,
                    self._schemas.get(channel.schema_id, ""),
                    record.log_time,
                    record.publish_time,
                    record.data if channel.topic in self.read else None,
                )

    def _checksum_right(self, stream: IO[bytes], end: int, crc: int) -> bool:
        """Whether the bytes before ``end`` have the data section's CRC."""
        if not self.verify:
            return True
        stream.seek(0)
        found, left = 0, end
        while left > 0:
            block = stream.read(min(_BLOCK, left))
            if not block:
                return False
            found, left = zlib.crc32(block, found), left - len(block)
        return found == crc


def _body(stream: IO[bytes], length: int) -> ReadDataStream:
    """The next ``length`` bytes, to parse one small record from."""
    return ReadDataStream(BytesIO(stream.read(length)))
