"""The decide service's model: the fit service's current one, followed live.

At start it first subscribes to ``<ns>/fit/model/update`` and watches the
fit service's liveliness token (``<ns>/alive/fit``), then asks the fit
service for its model (``<ns>/fit/model``). If the fit service is alive
(``armplan up`` starts decide once it is), this happens before the decide
service declares its own token, so a client seeing decide alive gets
decisions of fit's model; if fit gives none within ``FETCH_TIMEOUT``, a
warning is logged and the shipped default is used. If the fit service is not
running it starts with the shipped default and asks again as soon as the
fit service's token appears (a fit service started after it, or
restarted): asked only once at start, a decide service started a moment
before a fit service with a lab model used to decide with the shipped one
for good. Each model published on the topic is validated, compiled
(``Decider``) and swapped in between two requests, without a restart. A
malformed publication is logged and ignored; the model in use stays; so
is one larger than the bus's ``max_payload``, unread (a 200 MB one held
3.8 GB of the service's memory while parsed, a 60 MB list of empty
objects over 10 GB). An
answer of ``fit/model`` is dropped if a model was published after it was
asked for (the published one is newer), and a model already served (by
its digest) is not compiled again: a duplicate publication costs a hash,
not a compile (about 44 ms) on Zenoh's callback thread. When the service
stops, ``close`` undeclares its subscribers before the session closes
(the service's ``stopped`` hook, ``shared.bus.runner.Served``).

Each model it starts with or swaps in is logged with its digest, as the
fit service logs the model it serves (``services.fit.model_state.digest``:
12 hex digits of the SHA-256 of its JSON), e.g. ``serving model
3f2a9c0d1b7e (3879 samples, primitives ...) from the fit service``, so the
two logs show whether they use the same model.
"""

from __future__ import annotations

import logging
import threading

import zenoh

from services.decide.decider import Decider
from services.fit.default import default_model
from services.fit.model_state import digest
from shared.bus import Bus, NoArguments
from shared.bus.keys import alive_key
from shared.bus.routes import FIT_MODEL, MODEL_TOPIC
from shared.errors import ArmplanError
from shared.messages import MotionModel, parse

log = logging.getLogger("armplan.decide")
#: Longest wait for the fit service's model, at start or once it appears [s].
FETCH_TIMEOUT = 5.0


class LiveModel:
    """The compiled model the decisions use now, replaced when fit publishes.

    Args:
        bus: The decide service's bus; the first ask of ``fit/model`` waits
            up to ``FETCH_TIMEOUT`` (at once the default if fit is absent).

    Attributes:
        decider: The current model, compiled; read it once per request.
        updates: How many published models were swapped in.
        compiled: How many models were compiled (the one it starts with
            included); not one already served, nor an answer already stale.
    """

    decider: Decider

    def __init__(self, bus: Bus) -> None:
        self.updates = 0
        self.compiled = 0
        self._bus = bus
        self._lock = threading.Lock()  # guards what follows and the swap
        self._published = 0  # models received on the topic that can decide
        self._digest: str | None = None  # of the model served; None: none yet
        self._asking: list[threading.Thread] = []
        self._subscriber = bus.session.declare_subscriber(
            bus.key(MODEL_TOPIC), self._on_model
        )
        self._fit_token = bus.session.liveliness().declare_subscriber(
            alive_key(bus.config.namespace, FIT_MODEL.service), self._on_fit_token
        )
        fit_alive = FIT_MODEL.service in bus.alive()  # asked, not cached
        self._ask("the fit service")
        if self._digest is None:  # none came meanwhile (checked again inside)
            if fit_alive:
                log.warning(
                    "the fit service is alive but gave no model within %.0f s: "
                    "deciding with the shipped default until it publishes one",
                    FETCH_TIMEOUT,
                )
            until = "the shipped default, until the fit service starts"
            self._serve(default_model(), until, fallback=True)

    def _on_model(self, sample: zenoh.Sample) -> None:
        size, limit = len(sample.payload), self._bus.config.max_payload
        if size > limit:  # sized before copying: never read
            log.warning(
                "ignored a published model of %d bytes, over the bus's "
                "max_payload of %d bytes",
                size,
                limit,
            )
            return
        try:
            model = parse(MotionModel, sample.payload.to_bytes())
            swapped = self._serve(model, str(sample.key_expr), published=True)
        except ArmplanError as error:
            log.warning("ignored a published model: %s", error.message)
            return
        if swapped:
            self.updates += 1

    def _on_fit_token(self, sample: zenoh.Sample) -> None:
        """The fit service's token came (or went): ask for its model anew."""
        if sample.kind != zenoh.SampleKind.PUT:
            return
        log.info("the fit service started: asking for its model")
        asking = threading.Thread(
            target=self._ask,
            args=("the fit service, which started",),
            name="decide-ask-fit",
            daemon=True,
        )
        with self._lock:
            self._asking = [t for t in self._asking if t.is_alive()] + [asking]
        asking.start()  # not on Zenoh's thread: the query waits for a reply

    def _ask(self, source: str) -> None:
        """Ask ``fit/model`` and serve the answer unless one was published since."""
        with self._lock:
            asked = self._published
        try:
            model = self._bus.call(FIT_MODEL, NoArguments(), timeout=FETCH_TIMEOUT)
            self._serve(model, source, asked=asked)
        except ArmplanError as error:
            log.info("no model from %s: %s", source, error.message)
        except zenoh.ZError as error:  # the session closed meanwhile
            log.info("no model from %s: %s", source, error)

    def _serve(
        self,
        model: MotionModel,
        source: str,
        *,
        asked: int | None = None,
        published: bool = False,
        fallback: bool = False,
    ) -> bool:
        """Compile ``model`` and use it from the next request on.

        Whether it is wanted (not stale, not served already, not a fallback
        once one is served) is checked under the lock before it is compiled,
        and again after (a publication may have come meanwhile); compiling
        is outside the lock, so requests and other models do not wait on it.

        Args:
            model: The model.
            source: Where it came from, for the log.
            asked: ``fit/model`` answers only: the count of published models
                when it was asked for; dropped if one was published since.
            published: It came on the topic (an answer asked for before it
                arrived is older).
            fallback: Used only if no model is served yet (the default).

        Returns:
            Whether it is now served (``False``: stale, or served already).

        Raises:
            ArmplanError: the model cannot be compiled (nothing changes).
        """
        name = digest(model)
        with self._lock:
            if published and name == self._digest:  # compiled once already
                self._published += 1
                return False
            if self._unwanted(name, asked, fallback):
                return False
        decider = Decider(model)  # raises for a model that cannot decide
        with self._lock:
            self.compiled += 1
            if published:
                self._published += 1
            before = self._digest
            if self._unwanted(name, asked, fallback):
                return False
            self.decider = decider  # one assignment: requests see old or new
            self._digest = name
        log.info(
            "%s model %s (%d samples, primitives %s) from %s",
            "serving" if before is None else "swapped in",
            name,
            model.samples,
            ", ".join(model.primitives),
            source,
        )
        return True

    def _unwanted(self, name: str, asked: int | None, fallback: bool) -> bool:
        """Whether a model of digest ``name`` is not to be served (under the lock).

        Stale (a ``fit/model`` answer asked for before a publication came),
        served already, or a fallback once a model is served.
        """
        stale = asked is not None and asked != self._published
        return stale or name == self._digest or (fallback and self._digest is not None)

    def close(self) -> None:
        """Stop following the fit service (before the session closes)."""
        self._fit_token.undeclare()  # type: ignore[no-untyped-call]
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]
        with self._lock:
            asking = list(self._asking)
        for thread in asking:
            thread.join(FETCH_TIMEOUT)
        log.info("stopped following the fit service's model")
