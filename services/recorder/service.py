"""The recorder on Zenoh: subscribe to key expressions, hand samples to the sink.

Keys (namespace ``armplan`` by default):
    ``armplan/**``               one subscriber; samples whose key matches a
                                 recorded key expression are kept
    ``armplan/alive/recorder``   liveliness token while it records

One subscriber, not one per key expression: zenoh-python runs each
subscriber's callback on its own thread, so samples of different
subscribers would reach the writer out of the order they crossed the bus.
With one subscriber the file's order is the order the router sent them.

Run it with ``python -m services.recorder [-o FILE.mcap] [--keys K ...]``, or
in-process with :class:`Recorder` on an open :class:`~shared.bus.Bus`
(``armplan record`` does). The token is declared after the subscribers, so
a publisher that sees it knows its messages will be recorded.

Log time of each message: the Zenoh timestamp of the sample, which is the
publisher's when it sets one (``put(..., timestamp=session.new_timestamp())``)
and otherwise the router's, stamped as the sample enters it (Zenoh routers
have ``timestamping/enabled`` on by default; the project's router keeps it).
A sample without a timestamp (peer-to-peer, timestamping off) gets its
receipt time. Publish time is always the receipt time.
"""

from __future__ import annotations

import logging
import threading
import time
from pathlib import Path

import zenoh

from services.recorder.alive_check import warn_if_nobody_alive
from services.recorder.model_at_start import ModelAtStart, records_models
from services.recorder.options import RecorderOptions, check_keys
from services.recorder.routing import Incoming
from services.recorder.sink import RecordingSink
from shared.bus import Bus
from shared.bus.keys import alive_key
from shared.bus.session import has_router_or_peer
from shared.errors import RecordingError
from shared.lifecycle import StartStop
from shared.recording.rotation import parts_named
from shared.text.counted import counted

NAME = "recorder"
#: Period at which :meth:`Recorder.wait` checks the writer [s].
POLL = 0.2
log = logging.getLogger("armplan.recorder")


def log_time_of(sample: zenoh.Sample, received: int) -> int:
    """The sample's Zenoh timestamp [ns since the epoch], else ``received``."""
    stamp = sample.timestamp
    if stamp is None:
        return received
    return int(stamp.get_time_as_ntp64().as_nanos())


class Recorder(StartStop):
    """Records key expressions of one bus into MCAP files.

    Args:
        bus: An open bus (its namespace prefixes every key).
        options: What to record and where.

    Attributes:
        sink: The writer behind the subscriptions.
    """

    def __init__(self, bus: Bus, options: RecorderOptions | None = None) -> None:
        self.options = options or RecorderOptions()
        namespace = bus.config.namespace
        check_keys(self.options.keys, namespace)
        self.keys = [f"{namespace}/{key}" for key in self.options.keys]
        self.sink = RecordingSink(self.options, namespace, bus.config.max_payload)
        self._bus = bus
        self._exprs = [zenoh.KeyExpr(key) for key in self.keys]
        self._subscriber: zenoh.Subscriber[None] | None = None
        self._token: zenoh.LivelinessToken | None = None
        self._connected = True
        self.model_at_start: ModelAtStart | None = None

    def start(self) -> Recorder:
        """Open the file, subscribe, then announce liveliness.

        Warns (``alive_check``) when no armplan process is alive in the
        namespace: a wrong ``--namespace`` records nothing.

        Raises:
            RecordingError: if the file cannot be created.
        """
        self.sink.start()
        session = self._bus.session
        namespace = self._bus.config.namespace
        try:
            everything = f"{namespace}/**"
            self._subscriber = session.declare_subscriber(everything, self._on_sample)
            warn_if_nobody_alive(self._bus, NAME)
            self._token = session.liveliness().declare_token(alive_key(namespace, NAME))
            if records_models(self._exprs, namespace):
                self.model_at_start = ModelAtStart(self._bus, self.sink).start()
        except BaseException:  # leave nothing half-started: close the file
            self.stop()
            raise
        log.info("recording %s to %s", ", ".join(self.keys), self.sink.paths[0])
        return self

    def _on_sample(self, sample: zenoh.Sample) -> None:
        """Time-stamp and queue a sample of a recorded key (Zenoh's thread)."""
        received = time.time_ns()
        if sample.kind != zenoh.SampleKind.PUT:
            return
        if not any(expr.intersects(sample.key_expr) for expr in self._exprs):
            return
        if self.model_at_start is not None:
            self.model_at_start.saw(str(sample.key_expr))
        self.sink.put(
            Incoming(
                str(sample.key_expr),
                sample.payload.to_bytes(),
                str(sample.encoding),
                log_time_of(sample, received),
                received,
            )
        )

    def wait(self, stop: threading.Event, timeout: float | None = None) -> None:
        """Until ``stop`` is set, the file takes no more, or ``timeout`` [s] passes.

        Meanwhile it says when the router is lost and when it is back
        (:meth:`watch_router`): nothing is recorded in between.
        """
        deadline = None if timeout is None else time.monotonic() + timeout
        while not self.sink.broken.is_set():
            self.watch_router()
            left = POLL if deadline is None else min(POLL, deadline - time.monotonic())
            if left <= 0 or stop.wait(left):
                return

    def watch_router(self) -> None:
        """Log a warning when the router goes away, and when it comes back.

        Zenoh reconnects by itself; what is published while no router
        connects the recorder is not recorded, so the log says when. A peer
        on ``--connect`` (a peer-mode session listening there, which SPEC
        allows) counts as connected: it delivers what it receives, and
        counted as no router it had the log say "nothing is recorded" while
        the recording went on.
        """
        connected = has_router_or_peer(self._bus.session)
        if connected == self._connected:
            return
        self._connected = connected
        endpoints = ", ".join(self._bus.config.endpoints)
        if connected:
            log.warning("recorder: the router at %s is back; recording", endpoints)
        else:
            log.warning(
                "recorder: lost the router at %s; nothing is recorded until it "
                "is back (%s so far)",
                endpoints,
                counted(self.sink.written, "message"),
            )

    def stop(self) -> list[Path]:
        """Withdraw the token and subscriptions, write out the rest, close.

        Returns:
            The files written, in order (without the older parts
            ``--keep-parts`` removed).

        Raises:
            RecordingError: if the file system refused a write: the reason,
                how many messages were written, and how to read them.
        """
        if self._token is not None:
            self._token.undeclare()  # type: ignore[no-untyped-call]
            self._token = None
        if self._subscriber is not None:
            self._subscriber.undeclare()  # type: ignore[no-untyped-call]
            self._subscriber = None
        if self.model_at_start is not None:
            self.model_at_start.close()
        paths = self.sink.stop()
        derived = self.sink.derived
        log.info(
            "recorder stopped: %s from the bus%s in %s%s",
            counted(self.sink.written, "message"),
            f" (and {derived} derived for Foxglove)" if derived else "",
            self.sink.files_note(),
            self.sink.behind_note(),
        )
        if self.sink.error is not None:
            raise self._failed(self.sink.error)
        return paths

    def _failed(self, error: RecordingError) -> RecordingError:
        """The error of a recording the file system stopped: where its messages are.

        With rotation only the last part lacks its summary; it was said to
        hold them all ("--recover r-0006.mcap reads them" of 45 messages in
        6 parts, 3 of them in r-0006). With ``--keep-parts`` the parts
        removed on purpose are said to be gone, not whole.
        """
        written = counted(self.sink.written, "message")
        started = self.sink.started
        recover = (
            f"armplan inspect --recover {error.path} reads what it holds (it "
            "lacks its summary)"
        )
        where = (
            f"; armplan inspect --recover {error.path} reads them "
            "(the file lacks its summary)"
            if started <= 1
            else f" in {started} parts: {self._earlier(error.path)}{recover}"
        )
        return RecordingError(
            f"{error.message}; recording stopped after {written}{where}",
            path=error.path,
            readable=self.sink.written,
        )

    def _earlier(self, failed: str) -> str:
        """What became of the parts before ``failed``: ``"... are whole, and "``."""
        pruned = len(self.sink.pruned)
        if not pruned:
            return "the earlier parts are whole, and "
        kept = [path for path in self.sink.paths if str(path) != failed]
        oldest = "oldest part" if pruned == 1 else f"{pruned} oldest parts"
        keep = self.sink.options.rotation.keep_parts
        removed = f"the {oldest} removed (--keep-parts {keep})"
        if not kept:
            return f"{removed}; "
        verb = "is" if len(kept) == 1 else "are"
        return f"{removed}, {parts_named(kept)} {verb} whole, and "
