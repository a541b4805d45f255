"""The timing service: Ruckig time-parameterisation on Zenoh (skeleton).

Keys (namespace ``armplan`` by default):
    ``armplan/timing``  JointPath -> Trajectory (``shared.bus.routes.TIMING``)

Run it with ``python -m services.timing`` (``armplan up`` does). Until the
algorithm is wired, every request gets a typed ``endpoint_not_wired`` error.

TODO(lead): replace ``not_wired(...)`` below by the in-process timing function
of ``services.timing`` (``JointPath`` in, ``Trajectory`` out, or the request
message it needs for limits), and confirm the route in ``shared/bus/routes.py``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from shared.bus import Bus, Endpoint
from shared.bus.routes import TIMING
from shared.bus.skeleton import not_wired

NAME = "timing"


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The timing service's endpoints."""
    return [
        Endpoint(
            TIMING,
            not_wired(TIMING, bus.config.namespace, "Ruckig timing (services.timing)"),
        )
    ]
