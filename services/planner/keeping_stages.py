"""The in-process stages, keeping the last request each one got.

A plan made with them shows exactly what the planner asks each stage
service for: the benchmark sends those requests straight to the running
services (``armplan.bench.stage_hops``), and the fault suite uses them as
valid traffic and as templates for bad input (``armplan.faults.requests``).
"""

from __future__ import annotations

from services.planner.stages import LocalStages
from shared.bus.routes import DECIDE, IK_PATH, TIMING
from shared.messages import (
    DecideRequest,
    Decision,
    JointPath,
    Message,
    PathIKRequest,
    TimingRequest,
    Trajectory,
)


class KeepingStages(LocalStages):
    """:class:`LocalStages` that keep the last request of each stage.

    Attributes:
        asked: The last request by route path (``"decide"``, ``"ik/path"``,
            ``"timing"``).
    """

    def __init__(self) -> None:
        super().__init__()
        self.asked: dict[str, Message] = {}

    def decide(self, request: DecideRequest) -> Decision:
        self.asked[DECIDE.path] = request
        return super().decide(request)

    def ik(self, request: PathIKRequest) -> JointPath:
        self.asked[IK_PATH.path] = request
        return super().ik(request)

    def timing(self, request: TimingRequest) -> Trajectory:
        self.asked[TIMING.path] = request
        return super().timing(request)
