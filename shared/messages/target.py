"""Targets and tasks: what a client asks the planner for."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import Direction, JointVector, Message, Vec3
from shared.messages.method import Method
from shared.robot.side import Side

#: Most targets one task may hold.
MAX_TARGETS = 64


class ReachTarget(Message):
    """One wrist target of a task.

    Attributes:
        position: Wrist target in the torso frame [m].
        palm: Optional wrist orientation: the direction the palm should face,
            torso frame (unit length after validation).
        dwell: Time to hold still at the target before the next one [s].
    """

    position: Vec3
    palm: Direction | None = None
    dwell: float = Field(default=0.0, ge=0.0, le=60.0)


class PlanRequest(Message):
    """A task for the planner: reach one or more targets with one arm.

    Attributes:
        arm: Which arm moves.
        targets: Wrist targets, reached in order.
        start: Start posture [rad]; ``None`` means the arm hanging at rest.
        method: Planning method.
        fastest: Go as fast as the limits allow instead of at human pace.
        rate: Sample rate of the returned trajectory [Hz].
    """

    arm: Side = Side.RIGHT
    targets: list[ReachTarget] = Field(min_length=1, max_length=MAX_TARGETS)
    start: JointVector | None = None
    method: Method = Method.MP
    fastest: bool = False
    rate: float = Field(default=100.0, gt=0.0, le=1000.0)
