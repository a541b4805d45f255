"""The motion model served when a recording starts, asked of the fit service.

The fit service publishes its model on ``<ns>/fit/model/update`` when it
starts and after each fit. A recorder started later (``armplan record``
after ``armplan up``) saw neither: its decisions name the model that
decided them (``Decision.model``, a 12-hex digest) but the recording did not
hold that model. So a recorder whose keys take ``fit/model/update`` asks
``<ns>/fit/model`` once, on its own thread (the recording starts at once),
and records the answer on the channel ``<ns>/fit/model`` (schema
``MotionModel``): the model served when the recording started. Each later
file of a rotating recording starts with the last model recorded, on the
same channel (``sink.RecordingSink``); a replay sends none of them
(``replay_parts.to_send``): they were answers, not publications.

The answer is dropped if a model was published on ``fit/model/update``
after it was asked for (that one is newer, and recorded), or if the
recording stopped meanwhile. No fit service alive: nothing is asked, and a
model it publishes when it starts is recorded as usual.
"""

from __future__ import annotations

import logging
import threading
import time

import zenoh

from services.recorder.routing import ASKED_ENCODING, Incoming
from services.recorder.sink import RecordingSink
from shared.bus import Bus, NoArguments
from shared.bus.routes import FIT_MODEL, MODEL_TOPIC
from shared.errors import ArmplanError

log = logging.getLogger("armplan.recorder")
#: Longest wait for the fit service's answer [s] (as the decide service's).
ASK_TIMEOUT = 5.0


def records_models(exprs: list[zenoh.KeyExpr], namespace: str) -> bool:
    """Whether recorded key expressions ``exprs`` take ``<ns>/fit/model/update``."""
    update = zenoh.KeyExpr(f"{namespace}/{MODEL_TOPIC}")
    return any(expr.intersects(update) for expr in exprs)


class ModelAtStart:
    """Asks the fit service for its model once and records the answer.

    Args:
        bus: The recorder's bus.
        sink: Where the answer goes, as a received sample of ``<ns>/fit/model``.

    Attributes:
        recorded: Whether the answer was recorded.
    """

    def __init__(self, bus: Bus, sink: RecordingSink) -> None:
        self.recorded = False
        self._bus = bus
        self._sink = sink
        self._lock = threading.Lock()  # guards what follows and the put
        self._published = False  # a model came on fit/model/update
        self._closed = False
        self._update_key = bus.key(MODEL_TOPIC)
        self._thread = threading.Thread(
            target=self._ask, name="recorder-ask-model", daemon=True
        )

    def start(self) -> ModelAtStart:
        """Ask on a thread of its own; return at once."""
        self._thread.start()
        return self

    def saw(self, key: str) -> None:
        """A sample of ``key`` came: a published model makes the answer stale."""
        if key == self._update_key:
            with self._lock:
                self._published = True

    def close(self) -> None:
        """Record nothing from now on (the recording stops)."""
        with self._lock:
            self._closed = True

    def join(self, timeout: float) -> None:
        """Wait up to ``timeout`` [s] for the ask to end (tests)."""
        self._thread.join(timeout)

    def _ask(self) -> None:
        if FIT_MODEL.service not in self._bus.alive():
            log.info("recorder: no fit service alive; no model at the start")
            return
        try:
            model = self._bus.call(FIT_MODEL, NoArguments(), timeout=ASK_TIMEOUT)
        except ArmplanError as error:
            log.warning("recorder: no model from the fit service: %s", error.message)
            return
        except zenoh.ZError as error:  # the session closed meanwhile
            log.info("recorder: no model from the fit service: %s", error)
            return
        now = time.time_ns()
        sample = Incoming(
            self._bus.key(FIT_MODEL.path),
            model.model_dump_json().encode(),
            ASKED_ENCODING,
            now,
            now,
        )
        with self._lock:
            if self._published or self._closed:
                return
            self._sink.put(sample)
            self.recorded = True
        log.info("recorder: recorded the model served at the start")
