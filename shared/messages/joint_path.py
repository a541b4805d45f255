"""Joint paths (from IK) and trajectories (after timing)."""

from __future__ import annotations

from pydantic import Field, model_validator

from shared.messages.base import Message, OptionalFieldsMessage, Vec3
from shared.messages.method import Method
from shared.messages.palm_reached import PalmReached
from shared.messages.passing_times import check_passing_times
from shared.messages.sample_times import check_times
from shared.messages.target import MAX_TRAJECTORY_SAMPLES
from shared.robot.side import SideAnyCase

Row = list[float]


def _check_rows(name: str, rows: list[Row], n: int, width: int) -> None:
    if len(rows) != n:
        raise ValueError(f"{name} has {len(rows)} rows, expected {n} (one per time)")
    for i, row in enumerate(rows):
        if len(row) != width:
            raise ValueError(f"{name}[{i}] has {len(row)} values, expected {width}")


class JointPath(Message):
    """Joint angles along a wrist path, before timing.

    Attributes:
        arm: Which arm.
        joint_names: NAO joint names, shape (5,).
        times: Path times [s], shape (n,).
        positions: Joint angles [rad], shape (n, 5).
        primitives: The primitive that moved the arm at each time, shape (n,).
        wrist: Wrist position reached at each time [m], shape (n, 3).
    """

    arm: SideAnyCase
    joint_names: list[str] = Field(min_length=1)
    times: list[float] = Field(min_length=1, max_length=MAX_TRAJECTORY_SAMPLES)
    positions: list[Row]
    primitives: list[str]
    wrist: list[Vec3]

    @model_validator(mode="after")
    def _shapes(self) -> JointPath:
        n = len(self.times)
        _check_rows("positions", self.positions, n, len(self.joint_names))
        if len(self.primitives) != n or len(self.wrist) != n:
            raise ValueError("primitives and wrist need one entry per time")
        check_times(self.times)
        return self


class Trajectory(OptionalFieldsMessage):
    """A timed joint trajectory (the SPEC's trajectory JSON).

    Attributes:
        arm: Which arm.
        joint_names: NAO joint names, e.g. ``RShoulderPitch``, shape (5,).
        times: Sample times from the start [s], shape (n,).
        positions: Joint angles [rad], shape (n, 5).
        velocities: Joint speeds [rad/s], shape (n, 5).
        accelerations: Joint accelerations [rad/s^2], shape (n, 5).
        primitives: Primitive label at each time, shape (n,).
        wrist_path: Wrist position followed at each time [m], shape (n, 3).
        method: Planning method that made it.
        hand: The hand's open fraction at each time (0 closed, 1 open),
            shape (n,), for a task with hand actions; ``None`` (left out of
            the JSON) when the hand is not commanded. Its range and limits
            are the robot bridge's to check, as the joints' are.
        hand_velocities: The open fraction's rate at each time [1/s], shape
            (n,), as the planner made it (the bridge's curve between samples
            follows it, as the joints' follows ``velocities``); ``None``
            (left out of the JSON): not known, the bridge takes central
            differences of ``hand``. Only with ``hand``.
        hand_accelerations: Its rate of change [1/s^2], shape (n,); ``None``
            as ``hand_velocities``.
        point_times: When the trajectory passes each point of the joint
            paths it was timed from [s from its first sample], one list per
            segment of the timing request, shape (segments, points), not
            decreasing along the task (``services.timing.point_times``).
            The timing stage sets it for the planner, which moves each
            reach's list onto its decision (``Decision.trajectory_times``)
            and leaves it out of the plan's trajectory; ``None`` (left out
            of the JSON) otherwise.
        palm_reached: Where a palm direction was asked, the palm reached
            there: one entry per target of the task, in order (``None`` for
            a target without a palm), or one for a wrist path's palm, at its
            last sample. Only the palm's roll about the forearm is
            controlled, so the angle need not be 0. ``None`` (left out of
            the JSON) when no palm was asked.
    """

    omitted_when_none = (
        "hand",
        "hand_velocities",
        "hand_accelerations",
        "point_times",
        "palm_reached",
    )

    arm: SideAnyCase
    joint_names: list[str] = Field(min_length=1)
    times: list[float] = Field(min_length=1, max_length=MAX_TRAJECTORY_SAMPLES)
    positions: list[Row]
    velocities: list[Row]
    accelerations: list[Row]
    primitives: list[str]
    wrist_path: list[Vec3]
    method: Method = Method.MP
    hand: list[float] | None = None
    hand_velocities: list[float] | None = None
    hand_accelerations: list[float] | None = None
    point_times: list[list[float]] | None = None
    palm_reached: list[PalmReached | None] | None = None

    @model_validator(mode="after")
    def _shapes(self) -> Trajectory:
        n, width = len(self.times), len(self.joint_names)
        for name in ("positions", "velocities", "accelerations"):
            _check_rows(name, getattr(self, name), n, width)
        if len(self.primitives) != n or len(self.wrist_path) != n:
            raise ValueError("primitives and wrist_path need one entry per time")
        for name in ("hand", "hand_velocities", "hand_accelerations"):
            values = getattr(self, name)
            if values is not None and len(values) != n:
                raise ValueError(
                    f"{name} has {len(values)} values, expected {n} (one per time)"
                )
            if values is not None and self.hand is None:
                raise ValueError(f"{name} is given without hand")
        check_times(self.times)
        if self.point_times is not None:
            _check_point_times(self.point_times, self.duration)
        return self

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return self.times[-1] - self.times[0]


def _check_point_times(point_times: list[list[float]], duration: float) -> None:
    """Each list has a time, none decreases along the task, none passes the end.

    Raises:
        ValueError: naming the segment or the time at fault.
    """
    flat = [t for times in point_times for t in times]
    for k, times in enumerate(point_times):
        if not times:
            raise ValueError(f"point_times[{k}] is empty: a path has points")
    check_passing_times(flat, "point_times (joined)")
    if flat and flat[-1] > duration + 1e-9:
        raise ValueError(
            f"point_times end at {flat[-1]:.9g} s, after the trajectory's "
            f"{duration:.9g} s"
        )
