"""The planner service: the public entry point ``armplan/plan`` (skeleton).

Keys (namespace ``armplan`` by default):
    ``armplan/plan``             PlanRequest -> Trajectory (``routes.PLAN``)
    ``armplan/plan/trajectory``  publication: each finished Trajectory

The planner calls decide, ik and timing over Zenoh: ``bus.remote(route)`` is
each of them as a plain function, so the in-process planner algorithm can take
them as arguments and run the same code in-process and as a service. A
missing service gives a ``service_unavailable`` error naming it, within 2 s.

Run it with ``python -m services.planner`` (``armplan up`` does). Until the
algorithm is wired, every request gets a typed ``endpoint_not_wired`` error.

TODO(lead): replace ``not_wired(...)`` below by
``publishing(bus, partial(plan, decide=bus.remote(DECIDE),
ik=bus.remote(IK_PATH), timing=bus.remote(TIMING)))`` with the planner
function of ``services.planner`` (and the IK path route, see
``services/ik/service.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from shared.bus import Bus, Endpoint
from shared.bus.routes import PLAN, TRAJECTORY_TOPIC
from shared.bus.skeleton import not_wired
from shared.messages import PlanRequest, Trajectory

NAME = "planner"
Planner = Callable[[PlanRequest], Trajectory]


def publishing(bus: Bus, plan: Planner) -> Planner:
    """``plan``, publishing each trajectory it returns on ``plan/trajectory``."""

    def plan_and_publish(request: PlanRequest) -> Trajectory:
        trajectory = plan(request)
        bus.publish(TRAJECTORY_TOPIC, trajectory)
        return trajectory

    return plan_and_publish


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The planner's endpoints."""
    return [
        Endpoint(
            PLAN,
            not_wired(PLAN, bus.config.namespace, "the planner (services.planner)"),
        )
    ]
