"""The recorder's writer: received samples in, MCAP files out, on one thread.

Zenoh calls the recorder from its own threads; they only time-stamp each
sample and queue it (:meth:`RecordingSink.put` never blocks). One writer
thread takes the samples in arrival order, gives each its channel
(``routing.route``; a JSON object's channel notes the Zenoh encoding it came
with, for a replay), writes it and its derived Foxglove messages, and
flushes the file to the OS at least every ``flush_every`` seconds, also
when no message comes. :meth:`RecordingSink.stop` writes what is still
queued, then closes the file with its summary.

The queue is bounded by its bytes. A recorder that falls behind (planning
at 90 plans a second outpaced it on a 2-CPU machine, its memory growing
1.2 MB a second) first stops deriving Foxglove messages while more than
``SHED_BACKLOG`` bytes wait (``shed`` counts the samples left without them:
they are views of what is recorded, not data), and only past
``MAX_BACKLOG`` drops new samples (``dropped``); each episode is logged as
it starts and ends, and the counts are reported when the recording stops.

A sample that cannot be written (or whose Foxglove messages cannot be
made) is logged, counted and skipped. A file the file system refuses to
take more of (disk full, file too large) ends the writing: ``error`` holds
why, ``broken`` is set, and the recorder stops rather than keep receiving
what it can no longer keep.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from pathlib import Path

from services.recorder.options import RecorderOptions
from services.recorder.routing import (
    ASKED_ENCODING,
    Entry,
    Incoming,
    route,
    typed_schema,
)
from shared.bus.routes import FIT_MODEL
from shared.errors import RecordingError
from shared.messages import MotionModel
from shared.recording.foxglove import FoxgloveChannels, description_message
from shared.recording.metadata import ARMPLAN_METADATA
from shared.recording.raw_payload import ZENOH_ENCODING, RawPayload
from shared.recording.rotation import RotatingWriter, parts_named
from shared.recording.writer import MessageWriter
from shared.text.counted import counted

log = logging.getLogger("armplan.recorder")
#: Longest wait for the writer thread to write the queue out when stopping [s].
STOP_TIMEOUT = 30.0
#: Bytes waiting above which samples are written without their Foxglove
#: messages (a second of a busy planner's traffic).
SHED_BACKLOG = 16 * 2**20
#: Bytes waiting above which new samples are dropped: the recorder's memory
#: stays bounded, and the queue is written out within ``STOP_TIMEOUT``.
MAX_BACKLOG = 256 * 2**20


def _channel_metadata(entry: Entry, sample: Incoming) -> dict[str, str] | None:
    """The channel metadata of ``entry``: a JSON object's Zenoh encoding.

    A replay sends the object again with it; a ``RawPayload`` carries its own.
    """
    if entry.schema_name == RawPayload.__name__:
        return None
    return {ZENOH_ENCODING: sample.encoding}


class RecordingSink:
    """Writes received samples to a (rotating) live MCAP recording.

    Args:
        options: What to record and how.
        namespace: The bus namespace (topics are looked up relative to it).
        max_payload: Payloads larger than this are recorded raw, unread
            [bytes] (the bus's ``max_payload``: no service reads them);
            ``None``: every payload is read.

    Attributes:
        received: Samples queued so far.
        written: Samples written so far (derived messages not counted).
        derived: Messages armplan added for Foxglove so far (each file's robot
            description, poses derived from joint states and trajectories).
        failed: Samples that could not be written (logged).
        shed: Samples written without their Foxglove messages because the
            writer was behind.
        dropped: Samples not recorded because the writer was too far behind.
        error: Why the writing ended early (the file system refused more),
            or ``None``.
        broken: Set when ``error`` is.
    """

    def __init__(
        self,
        options: RecorderOptions,
        namespace: str,
        max_payload: int | None = None,
        shed_backlog: int = SHED_BACKLOG,
        max_backlog: int = MAX_BACKLOG,
    ) -> None:
        self.options = options
        self.namespace = namespace
        self.max_payload = max_payload
        self.received = 0
        self.written = 0
        self.derived = 0
        self.failed = 0
        self.shed = 0
        self.dropped = 0
        self._shed_backlog, self._max_backlog = shed_backlog, max_backlog
        self._backlog = 0  # payload bytes queued and not yet written
        self._backlog_lock = threading.Lock()
        self._dropping = self._shedding = False
        self.error: RecordingError | None = None
        self.broken = threading.Event()
        self._queue: queue.SimpleQueue[Incoming | None] = queue.SimpleQueue()
        self._model: bytes | None = None  # the last model written, its JSON
        self._recording_ns: int | None = None  # when part 1 started [ns]
        self._files = RotatingWriter(
            options.output,
            options.rotation,
            self._on_open,
            options.flush_every,
            overwrite=options.overwrite,
        )
        self._foxglove = (
            FoxgloveChannels(
                options.planned_prefix,
                options.executed_prefix,
                options.commanded_prefix,
            )
            if options.foxglove
            else None
        )
        self._thread = threading.Thread(
            target=self._run, name="recorder-writer", daemon=True
        )

    @property
    def paths(self) -> list[Path]:
        """The files written so far and not removed (``--keep-parts``), in order."""
        return list(self._files.paths)

    @property
    def queued(self) -> int:
        """Samples received and not yet written (with their Foxglove messages)."""
        return self._queue.qsize()

    @property
    def started(self) -> int:
        """Files started so far, removed ones included (1 without rotation)."""
        return self._files.started

    @property
    def pruned(self) -> list[Path]:
        """The older parts removed so far (``--keep-parts``), in order."""
        return list(self._files.pruned)

    def files_note(self) -> str:
        """The files on disk, and how many older ones were removed if any.

        E.g. ``5 parts, the newest 2 kept: s-0004.mcap, s-0005.mcap (3 older
        parts removed, --keep-parts 2)``: the messages counted before it are
        the whole recording's, most of them in the parts removed.
        """
        paths = self.paths
        files = parts_named(paths)
        pruned = len(self._files.pruned)
        if not pruned:
            return files
        keep = self.options.rotation.keep_parts
        return (
            f"{self._files.started} parts, the newest {len(paths)} kept: {files} "
            f"({counted(pruned, 'older part')} removed, "
            f"--keep-parts {keep})"
        )

    def start(self) -> RecordingSink:
        """Create the first file and start the writer thread.

        Raises:
            RecordingError: if the file cannot be created.
        """
        self._files.open()
        self._thread.start()
        return self

    def put(self, sample: Incoming) -> None:
        """Queue one received sample (never blocks; any thread).

        Dropped, and counted, while ``max_backlog`` bytes or more wait.
        """
        with self._backlog_lock:
            self.received += 1
            if self._backlog >= self._max_backlog:
                self.dropped += 1
                if not self._dropping:
                    self._dropping = True
                    log.warning(
                        "recorder: %d MB waiting to be written; dropping new "
                        "samples until it catches up",
                        self._backlog // 2**20,
                    )
                return
            self._backlog += len(sample.payload)
        self._queue.put(sample)

    def behind_note(self) -> str:
        """``"; the writer fell behind: ..."`` with what it cost, or ``""``."""
        lost = []
        if self.dropped:
            lost.append(f"{counted(self.dropped, 'sample')} dropped")
        if self.shed:
            lost.append(f"{self.shed} written without Foxglove poses")
        return f"; the writer fell behind: {', '.join(lost)}" if lost else ""

    def _taken(self, sample: Incoming) -> bool:
        """Count ``sample`` out of the backlog; whether the writer is behind."""
        with self._backlog_lock:
            self._backlog -= len(sample.payload)
            behind = self._backlog > self._shed_backlog
            if self._dropping and self._backlog < self._max_backlog // 2:
                self._dropping = False
                log.warning(
                    "recorder: caught up; %s dropped so far",
                    counted(self.dropped, "sample"),
                )
        if behind != self._shedding:
            self._shedding = behind
            if behind:
                log.warning(
                    "recorder: over %d MB waiting to be written; writing samples "
                    "without their Foxglove poses until it catches up",
                    self._shed_backlog // 2**20,
                )
            else:
                log.warning(
                    "recorder: caught up; %s written without Foxglove poses so far",
                    counted(self.shed, "sample"),
                )
        return behind

    def stop(self, timeout: float = STOP_TIMEOUT) -> list[Path]:
        """Write out the queue, close the file with its summary; the files written.

        A writer still busy after ``timeout`` [s] (a backlog of large
        messages) leaves the file without its summary: that is ``error``, so
        the recording is not reported whole (it was, with exit code 0).
        """
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join(timeout)
            if self._thread.is_alive():  # the file stays open: no summary
                self._fail(
                    RecordingError(
                        f"the writer was still busy {timeout:.0f} s after the stop, "
                        f"about {counted(self._queue.qsize(), 'message')} unwritten",
                        path=str(self.paths[-1]),
                    )
                )
        if not self._thread.is_alive():
            try:
                self._files.close()
            except RecordingError as error:
                self._fail(error)
        return self.paths

    def _run(self) -> None:
        """Write samples until the stop sentinel or a refused write."""
        try:
            self._drain()
        except RecordingError as error:
            self._fail(error)

    def _fail(self, error: RecordingError) -> None:
        """Keep the first reason the writing ended, and say it."""
        if self.error is None:
            self.error = error
            log.error(
                "recorder: %s; stopped after %s",
                error.message,
                counted(self.written, "message"),
            )
        self.broken.set()

    def _drain(self) -> None:
        """Write samples in arrival order until the stop sentinel.

        Under traffic the live writer flushes on a write once ``flush_every``
        has passed since its last flush; when no sample comes for half of it,
        this flushes whatever is buffered.

        Raises:
            RecordingError: the file system refused a write.
        """
        while True:
            try:
                sample = self._queue.get(timeout=self.options.flush_every / 2)
            except queue.Empty:
                self._files.flush()
                continue
            if sample is None:
                return
            self._write(sample, behind=self._taken(sample))

    def _write(self, sample: Incoming, behind: bool = False) -> None:
        try:
            entry = route(sample, self.namespace, self.max_payload)
            self._files.write(
                entry.topic,
                entry.schema_name,
                entry.schema,
                entry.data,
                sample.log_time,
                sample.publish_time,
                metadata=_channel_metadata(entry, sample),
            )
            self.written += 1
            if isinstance(entry.message, MotionModel):
                self._model = entry.data
        except RecordingError:
            raise  # the file takes no more: see _run
        except Exception:  # a writer keeps writing: log, count, go on
            self.failed += 1
            log.exception("recorder: could not write a sample of %s", sample.key)
            return
        if (
            behind
            and self._foxglove is not None
            and entry.message is not None
            and self._foxglove.derives(entry.message)
        ):
            self.shed += 1
            return
        self._derive(entry, sample)

    def _derive(self, entry: Entry, sample: Incoming) -> None:
        """Write the Foxglove messages of a typed sample; skip them if they fail.

        The sample itself is written already: a message that cannot be shown
        (a missing joint, times beyond MCAP's range) only loses its poses.
        They are written as they are made, one at a time (a trajectory of
        40 000 samples makes 80 000): the recorder never holds them all.
        """
        if self._foxglove is None or entry.message is None:
            return
        try:
            derived = self._foxglove.derive(entry.message, sample.log_time)
        except KeyError as missing:
            log.warning(
                "recorder: %s lacks joint %s; no Foxglove poses", entry.topic, missing
            )
            return
        except (ArithmeticError, ValueError) as error:
            log.warning("recorder: no Foxglove poses for %s: %s", entry.topic, error)
            return
        try:
            for d in derived:
                self._files.write(
                    d.topic,
                    d.schema_name,
                    d.schema,
                    d.data,
                    d.log_time,
                    sample.publish_time,
                    may_rotate=False,  # in the sample's own file
                )
                self.derived += 1
        except RecordingError:
            raise  # the file takes no more: see _run
        except Exception:  # a writer keeps writing: log and go on
            log.exception("recorder: Foxglove poses of %s cut short", entry.topic)

    def _on_open(self, writer: MessageWriter, number: int) -> None:
        """Start a file: the recorder's metadata, the robot description, the model.

        A file after the first starts with the last motion model recorded
        (asked at the start or published since) on ``<ns>/fit/model``: each
        file stands alone, its decisions' model with it.
        """
        now = time.time_ns()
        if self._recording_ns is None:
            self._recording_ns = now
        writer.add_metadata(
            ARMPLAN_METADATA,
            {
                "namespace": self.namespace,
                "keys": ",".join(self.options.keys),
                "part": str(number),
                "started_ns": str(now),
                # the recording's, in every part: replay tells two apart
                "recording_ns": str(self._recording_ns),
                "log_time": "zenoh timestamp of the sample, else its receipt time",
            },
        )
        if self._foxglove is not None:
            d = description_message(now)
            channel = writer.add_channel(d.topic, d.schema_name, d.schema)
            writer.write_raw(channel, d.data, d.log_time, d.log_time)
            self.derived += 1
        if self._model is not None:
            model = writer.add_channel(
                f"{self.namespace}/{FIT_MODEL.path}",
                MotionModel.__name__,
                typed_schema(MotionModel),
                {ZENOH_ENCODING: ASKED_ENCODING},
            )
            writer.write_raw(model, self._model, now, now)
        writer.flush()
