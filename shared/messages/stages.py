"""Requests between the planner and its stage services (decide, ik, timing)."""

from __future__ import annotations

from pydantic import Field, ValidationInfo, field_validator

from shared.messages.base import (
    DEFAULT_PLAN_RATE,
    MAX_RATE,
    MIN_PLAN_RATE,
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
        decision: The primitive of each point (method ``mp``): the decision
            made for this path, so of the path's arm and at exactly its
            times (checked on input).
        measures: The human performance measures' weights; ``None``: the
            decision's (method ``mp``), else the shipped ones.
    """

    path: WristPath
    start: JointVector | None = None
    method: Method = Method.MP
    decision: Decision | None = None
    measures: MeasureParams | None = None

    @field_validator("decision")
    @classmethod
    def _decision_fits(
        cls, decision: Decision | None, info: ValidationInfo
    ) -> Decision | None:
        path = info.data.get("path")  # absent if the path itself was refused
        if decision is not None and path is not None:
            check_decision_fits(decision, path)
        return decision

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
    rate: float = Field(default=DEFAULT_PLAN_RATE, ge=MIN_PLAN_RATE, le=MAX_RATE)
    method: Method = Method.MP
    limits: TimingLimits | None = None


def check_decision_fits(decision: Decision, path: WristPath) -> None:
    """``decision`` was made for ``path``: the same arm, the same times.

    The times must be equal exactly: a decision carries its path's times
    as decide read them, and JSON gives floats back bit for bit.

    Raises:
        ValueError: naming the decision's and the path's arm, point count
            or first differing time.
    """
    if decision.arm != path.arm:
        raise ValueError(
            f"the decision is for the {decision.arm.value} arm, "
            f"the wrist path for the {path.arm.value}"
        )
    if len(decision.times) != len(path.times):
        raise ValueError(
            f"the decision has {len(decision.times)} points, "
            f"the wrist path {len(path.times)}"
        )
    for k, (made, asked) in enumerate(zip(decision.times, path.times, strict=True)):
        if made != asked:
            raise ValueError(
                f"the decision was made for other times than the wrist path's: "
                f"point {k} at t = {made!r} s in the decision, "
                f"t = {asked!r} s in the path"
            )
