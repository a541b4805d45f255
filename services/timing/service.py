"""The timing service: Ruckig time-parameterisation on Zenoh.

Keys (namespace ``armplan`` by default):
    ``armplan/timing``  TimingRequest -> Trajectory (``shared.bus.routes.TIMING``)

The handler is the planner's timing stage (``services.planner.timing_stage.timing``):
a task's joint paths, each at its wanted duration, as one jerk-limited
trajectory within the arm's limits. Run it with ``python -m services.timing``
(``armplan up`` does).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from services.planner.timing_stage import timing
from shared.bus import Bus, Endpoint
from shared.bus.routes import TIMING
from shared.messages import TimingRequest, Trajectory

NAME = "timing"


def time_task(request: TimingRequest) -> Trajectory:
    """The trajectory of the request's joint paths, with the arm's own limits."""
    return timing(request)


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The timing service's endpoints (it calls no other service)."""
    return [Endpoint(TIMING, time_task)]
