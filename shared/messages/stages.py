"""Requests between the planner and its stage services (decide, ik, timing)."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import (
    MAX_RATE,
    MIN_RATE,
    JointVector,
    Message,
    OptionalFieldsMessage,
)
from shared.messages.decision import Decision
from shared.messages.hand import HandAction
from shared.messages.joint_path import JointPath
from shared.messages.measure_params import MeasureParams
from shared.messages.method import Method
from shared.messages.timing_limits import TimingLimits
from shared.messages.wrist_path import MAX_DURATION, WristPath


class DecideRequest(Message):
    """Decide the primitive of every point of one reach's wrist path.

    Attributes:
        path: The wrist path; its last point is the goal, its ``palm`` the
            wanted palm direction there.
        start: Posture at the first point [rad]; None: the arm at rest.
        measures: The human performance measures' weights; ``None``: the
            motion model's (the decision says which it used).
    """

    path: WristPath
    start: JointVector | None = None
    measures: MeasureParams | None = None


class PathIKRequest(Message):
    """Joint angles along one reach's wrist path.

    Attributes:
        path: The wrist path (goal: its last point; ``palm`` at the goal).
        start: Posture at the first point [rad]; None: the arm at rest.
        method: ``mp`` (needs ``decision``), ``least-norm`` or ``single``.
        decision: The primitive of each point (method ``mp``).
        measures: The human performance measures' weights; ``None``: the
            decision's (method ``mp``), else the shipped ones.
    """

    path: WristPath
    start: JointVector | None = None
    method: Method = Method.MP
    decision: Decision | None = None
    measures: MeasureParams | None = None

    def weights(self) -> MeasureParams:
        """The weights to track with: the request's, the decision's, or the shipped."""
        if self.measures is not None:
            return self.measures
        if self.decision is not None:
            return self.decision.measures
        return MeasureParams()


class TimingSegment(OptionalFieldsMessage):
    """One movement of a task and the rest after it.

    Attributes:
        joint_path: The movement's joint path (from the IK stage).
        duration: Wanted duration [s] (human pace), at most 600, or None:
            the fastest.
        dwell: Rest at the movement's end [s].
        hand: Hand action during the rest, or None (left out of the JSON).
    """

    omitted_when_none = ("hand",)

    joint_path: JointPath
    duration: float | None = Field(default=None, gt=0.0, le=MAX_DURATION)
    dwell: float = Field(default=0.0, ge=0.0, le=60.0)
    hand: HandAction | None = None


class TimingRequest(Message):
    """Time a task's movements as one trajectory.

    Attributes:
        segments: The movements, in order; each starts where the last ended.
        rate: Sample rate of the trajectory [Hz].
        method: The method that made the joint paths (carried to the result).
        limits: Acceleration and jerk limits to time with; ``None``: the
            defaults.
    """

    segments: list[TimingSegment] = Field(min_length=1, max_length=64)
    rate: float = Field(default=100.0, ge=MIN_RATE, le=MAX_RATE)
    method: Method = Method.MP
    limits: TimingLimits | None = None
