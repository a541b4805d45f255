"""The fit service: serves and publishes the motion model on Zenoh (skeleton).

Keys (namespace ``armplan`` by default):
    ``armplan/fit/model``         query: NoArguments -> the current model
    ``armplan/fit/model/update``  publication: each newly fitted model

Run it with ``python -m services.fit`` (``armplan up`` does). Until the
algorithm is wired, every request gets a typed ``endpoint_not_wired`` error.

TODO(lead):
- a model message in ``shared/messages`` replaces ``OpaqueMessage`` in
  ``shared.bus.routes.FIT_MODEL``;
- replace ``not_wired(...)`` below by a function returning the current model
  of ``services.fit``;
- when a new model is fitted, ``bus.publish(MODEL_TOPIC, model)`` so that the
  decide service swaps it in without a restart.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from shared.bus import Bus, Endpoint
from shared.bus.routes import FIT_MODEL
from shared.bus.skeleton import not_wired

NAME = "fit"


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The fit service's endpoints."""
    return [
        Endpoint(
            FIT_MODEL,
            not_wired(
                FIT_MODEL, bus.config.namespace, "the motion model (services.fit)"
            ),
        )
    ]
