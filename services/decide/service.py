"""The decide service: the motion decision on Zenoh.

Keys (namespace ``armplan`` by default):
    ``armplan/decide``  DecideRequest -> Decision (``shared.bus.routes.DECIDE``)

The handler is the planner's decide stage (``services.planner.stages.decide``)
with the model the fit service serves, followed live (``live_model.py``): a
model published on ``armplan/fit/model/update`` is used from the next
request on, without a restart. Run it with ``python -m services.decide``
(``armplan up`` does); when it stops, it stops following the fit service
(``LiveModel.close``) before its session closes.
"""

from __future__ import annotations

from collections.abc import Callable

from services.decide.live_model import LiveModel
from services.planner.stages import decide
from shared.bus import Bus, Endpoint
from shared.bus.routes import DECIDE
from shared.bus.runner import Served
from shared.messages import DecideRequest, Decision

NAME = "decide"


def deciding(model: LiveModel) -> Callable[[DecideRequest], Decision]:
    """The decide stage with ``model``'s current model."""

    def decide_request(request: DecideRequest) -> Decision:
        return decide(model.decider, request)[0]

    return decide_request


def endpoints(bus: Bus) -> Served:
    """The decide service's endpoints; it follows fit's model until it stops."""
    model = LiveModel(bus)
    return Served([Endpoint(DECIDE, deciding(model))], stopped=model.close)
