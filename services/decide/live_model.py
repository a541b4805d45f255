"""The decide service's model: the fit service's current one, followed live.

At start it asks the fit service for its model (``<ns>/fit/model``); if the
fit service is not running it starts with the shipped default, which is also
what a fit service starts with. It then follows ``<ns>/fit/model/update``:
each model published there is validated, compiled (``Decider``) and swapped
in between two requests, without a restart. A malformed publication is
logged and ignored; the model in use stays.
"""

from __future__ import annotations

import logging

import zenoh

from services.decide.decider import Decider
from services.fit.default import default_model
from shared.bus import Bus, NoArguments
from shared.bus.routes import FIT_MODEL, MODEL_TOPIC
from shared.errors import ArmplanError
from shared.messages import MotionModel, parse

log = logging.getLogger("armplan.decide")
#: Longest wait for the fit service's model at start [s].
FETCH_TIMEOUT = 5.0


class LiveModel:
    """The compiled model the decisions use now, replaced when fit publishes.

    Attributes:
        decider: The current model, compiled; read it once per request.
        updates: How many published models were swapped in.
    """

    def __init__(self, bus: Bus) -> None:
        self.decider = Decider(_initial(bus))
        self.updates = 0
        self._subscriber = bus.session.declare_subscriber(
            bus.key(MODEL_TOPIC), self._on_model
        )

    def _on_model(self, sample: zenoh.Sample) -> None:
        try:
            model = parse(MotionModel, sample.payload.to_bytes())
            decider = Decider(model)
        except ArmplanError as error:
            log.warning("ignored a published model: %s", error.message)
            return
        self.decider = decider  # one assignment: requests see old or new
        self.updates += 1
        log.info("swapped in a new model (%d samples)", model.samples)

    def close(self) -> None:
        """Stop following updates (before the session closes)."""
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]


def _initial(bus: Bus) -> MotionModel:
    """The fit service's current model, or the default if it is not running."""
    try:
        return bus.call(FIT_MODEL, NoArguments(), timeout=FETCH_TIMEOUT)
    except ArmplanError as error:
        log.info("starting with the default model (%s)", error.message)
        return default_model()
