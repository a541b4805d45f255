"""Write armplan messages to an MCAP file.

One channel per topic (key expression), JSON messages, and per message class
one schema: the class's JSON schema from pydantic (encoding ``jsonschema``),
named after the class. Foxglove and the ``mcap`` CLI read the files as is.

Two layouts:
    chunked (default): compressed chunks, for files written in one go
        (demonstration sets); only ``close()`` writes the summary.
    live (``chunked=False``): every message is its own record, flushed to
        the OS at least every ``flush_every`` seconds, so a writer killed
        with SIGKILL loses at most that much; :func:`read_records` with
        ``recover=True`` reads such a file back without its summary.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import IO, Any

from mcap.writer import CompressionType, Writer

from shared.errors import InvalidInputError, RecordingError
from shared.lifecycle import Closes
from shared.messages.base import Message
from shared.recording.file_lock import hold, open_locked

PROFILE = "armplan"


class MessageWriter(Closes):
    """An MCAP writer for pydantic messages.

    Every write, flush and close that the file system refuses (disk full,
    file too large, device gone) raises :class:`RecordingError` naming the
    file and the reason; the file then lacks its summary, and
    ``read_records(..., recover=True)`` reads what reached it.

    Args:
        path: File to create.
        chunked: Compressed chunks (offline) or one record per message (live).
        flush_every: Live layout only: longest time between flushes [s].
        overwrite: Replace an existing file (unlinked, then a new one
            created: never emptied in place), unless another writer holds
            it; if False, an existing file is refused. Either way the file
            is created exclusively and held (``file_lock``) until closed,
            so two writers never share it.

    Raises:
        RecordingError: if the file cannot be created or written, is a
            folder, exists and ``overwrite`` is False, or another writer
            is writing it (``overwrite`` or not).
    """

    def __init__(
        self,
        path: str | Path,
        *,
        chunked: bool = True,
        flush_every: float = 0.2,
        overwrite: bool = True,
    ):
        self.path = Path(path)
        refuse_folder(self.path)
        try:
            self._file: IO[bytes] = open_locked(self.path, overwrite=overwrite)
        except IsADirectoryError:  # made meanwhile
            raise folder_error(self.path) from None
        except RecordingError:
            if self.path.is_dir():  # made meanwhile
                raise folder_error(self.path) from None
            raise
        except OSError as exc:
            raise RecordingError(
                f"cannot create {self.path}: {exc.strerror}", path=str(self.path)
            ) from None
        self._writer = Writer(
            self._file,
            chunk_size=256 * 1024,
            compression=CompressionType.ZSTD if chunked else CompressionType.NONE,
            use_chunking=chunked,
            enable_data_crcs=True,
        )
        self.closed = False
        try:
            with self._writing():
                self._writer.start(profile=PROFILE, library="armplan")
                self._file.flush()
        except RecordingError:
            self._abandon()
            raise
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._typed: dict[tuple[str, type[Message]], int] = {}
        self._typed_channels: dict[tuple[Any, ...], int] = {}
        self._chunked = chunked
        self._flush_every = flush_every
        self._last_flush = time.monotonic()
        self.count = 0

    def _abandon(self) -> None:
        """Close the file without its summary, whatever the file system says."""
        self.closed = True
        with suppress(OSError):  # the bytes it could not take are lost either way
            self._file.close()

    @contextmanager
    def _writing(self) -> Iterator[None]:
        """Turn the file system's refusal into a :class:`RecordingError`."""
        try:
            yield
        except OSError as exc:
            raise RecordingError(
                f"cannot write {self.path}: {exc.strerror or exc}", path=str(self.path)
            ) from None

    def schema_id(self, name: str, schema: dict[str, Any]) -> int:
        """The id of schema ``name``, registering it on first use."""
        if name not in self._schemas:
            data = json.dumps(schema).encode()
            with self._writing():
                sid = self._writer.register_schema(name, "jsonschema", data)
            self._schemas[name] = sid
        return self._schemas[name]

    def channel_id(self, topic: str, schema_name: str, schema: dict[str, Any]) -> int:
        """The id of the channel for ``topic``, registering it on first use."""
        if topic not in self._channels:
            sid = self.schema_id(schema_name, schema)
            with self._writing():
                self._channels[topic] = self._writer.register_channel(
                    topic, "json", sid
                )
        return self._channels[topic]

    def add_channel(
        self,
        topic: str,
        schema_name: str,
        schema: dict[str, Any],
        metadata: dict[str, str] | None = None,
    ) -> int:
        """The id of the channel for ``topic`` with schema ``schema_name``.

        Unlike :meth:`channel_id`, one topic may have several channels, one
        per schema and ``metadata`` (e.g. a typed channel and a schemaless
        ``"json"`` one for payloads that do not parse as the topic's class;
        the recorder notes each payload's Zenoh encoding in ``metadata``).
        Registers on first use.
        """
        key = (topic, schema_name, *(metadata or {}).items())
        if key not in self._typed_channels:
            sid = self.schema_id(schema_name, schema)
            with self._writing():
                self._typed_channels[key] = self._writer.register_channel(
                    topic, "json", sid, dict(metadata or {})
                )
        return self._typed_channels[key]

    def add_metadata(self, name: str, data: dict[str, str]) -> None:
        """Append a metadata record ``name`` (string keys and values)."""
        with self._writing():
            self._writer.add_metadata(name, data)

    @property
    def size(self) -> int:
        """Bytes written to the file so far [bytes] (buffered ones included)."""
        return self._file.tell()

    def write(
        self,
        topic: str,
        message: Message,
        log_time: int,
        publish_time: int | None = None,
    ) -> None:
        """Append ``message`` on ``topic``.

        Args:
            topic: Channel topic (the Zenoh key expression).
            message: The message.
            log_time: When the message was made [ns since the epoch].
            publish_time: When it was received [ns]; defaults to ``log_time``.
        """
        channel = self._channel_for(topic, type(message))
        self.write_raw(channel, message.to_json().encode(), log_time, publish_time)

    def _channel_for(self, topic: str, cls: type[Message]) -> int:
        """The channel of ``topic`` for messages of ``cls`` (schema built once)."""
        key = (topic, cls)
        if key not in self._typed:
            self._typed[key] = self.channel_id(topic, cls.__name__, cls.json_schema())
        return self._typed[key]

    def write_raw(
        self, channel: int, data: bytes, log_time: int, publish_time: int | None = None
    ) -> None:
        """Append already-encoded JSON ``data`` on a registered channel.

        Raises:
            InvalidInputError: if a time is outside MCAP's range (0 to 2^64 ns).
            RecordingError: if the file system refuses the write.
        """
        publish_time = log_time if publish_time is None else publish_time
        check_time(log_time, "log_time")
        check_time(publish_time, "publish_time")
        with self._writing():
            self._writer.add_message(
                channel,
                log_time=log_time,
                data=data,
                publish_time=publish_time,
                sequence=self.count,
            )
        self.count += 1
        if (
            not self._chunked
            and time.monotonic() - self._last_flush >= self._flush_every
        ):
            self.flush()

    #: The file as closed with its summary (size, modification time), by its
    #: descriptor; ``None`` until then.
    final: os.stat_result | None = None

    @property
    def identity(self) -> tuple[int, int]:
        """The file's device and inode (``st_dev``, ``st_ino``)."""
        info = os.fstat(self._file.fileno())
        return info.st_dev, info.st_ino

    def hold(self) -> int:
        """A second descriptor of the file, holding it against other writers.

        It keeps the file held (``file_lock``) past :meth:`close`, until
        ``os.close`` closes it.
        """
        return hold(self._file)

    def flush(self) -> None:
        """Push buffered bytes to the OS (live layout: everything written so far)."""
        with self._writing():
            self._file.flush()
        self._last_flush = time.monotonic()

    def close(self) -> None:
        """Write the summary and close the file. Safe to call twice."""
        if self.closed:
            return
        self.closed = True
        with self._writing():
            try:
                self._writer.finish()  # type: ignore[no-untyped-call]
                self._file.flush()
                self.final = os.fstat(self._file.fileno())
            finally:
                self._file.close()


def folder_error(path: Path) -> RecordingError:
    """The error for a recording path that names a folder."""
    return RecordingError(
        f"{path} is a folder: name the recording's file, e.g. {path / 'session.mcap'}",
        path=str(path),
    )


def refuse_folder(path: str | Path) -> None:
    """Refuse a recording path that is a folder (``--overwrite`` cannot help).

    Raises:
        RecordingError: naming the folder (not "exists": replacing a folder
            with a recording is never what was meant).
    """
    if Path(path).is_dir():
        raise folder_error(Path(path))


#: Largest time an MCAP record holds [ns since the epoch] (unsigned 64 bits).
MAX_TIME = 2**64 - 1


def check_time(value: int, name: str) -> None:
    """Refuse a time [ns] outside MCAP's range before any byte is written.

    Raises:
        InvalidInputError: naming ``name`` and the value.
    """
    if not 0 <= value <= MAX_TIME:
        raise InvalidInputError(
            f"{name} {value} ns is outside MCAP's range (0 to 2^64 ns)", field=name
        )
