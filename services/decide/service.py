"""The decide service: the motion decision on Zenoh (skeleton).

Keys (namespace ``armplan`` by default):
    ``armplan/decide``  WristPath -> Decision (``shared.bus.routes.DECIDE``)

Run it with ``python -m services.decide`` (``armplan up`` does). Until the
algorithm is wired, every request gets a typed ``endpoint_not_wired`` error.

TODO(lead):
- replace ``not_wired(...)`` below by the in-process decision function of
  ``services.decide`` (request message in, ``Decision`` out), and confirm the
  route's message types in ``shared/bus/routes.py``;
- pick up new models without a restart: in ``endpoints``, subscribe to
  ``bus.key(MODEL_TOPIC)`` with ``bus.session.declare_subscriber(key,
  callback)`` and swap the model the decision function reads; fetch the
  current one at start with ``bus.call(FIT_MODEL, NoArguments())``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from shared.bus import Bus, Endpoint
from shared.bus.routes import DECIDE
from shared.bus.skeleton import not_wired

NAME = "decide"


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The decide service's endpoints."""
    return [
        Endpoint(
            DECIDE,
            not_wired(
                DECIDE, bus.config.namespace, "the motion decision (services.decide)"
            ),
        )
    ]
