"""Command frames for the robot, and what the robot did with them.

A trajectory becomes *command frames*: joint angles at the frames of a
timeline (Choregraphe's, 25 fps by default). Frame ``k`` (``k = 1 .. m``) is
reached ``k / rate`` seconds after the start; the start posture itself is
frame 0. The bridge sends the frames to a NAO (real or simulated), samples
the measured angles while it moves, and answers with the executed joint
states and a tracking report.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, NonNegativeFloat, model_validator

from shared.messages.base import MAX_RATE, MIN_RATE, Message, OptionalFieldsMessage
from shared.messages.joint_path import Row, Trajectory
from shared.messages.sample_times import check_times
from shared.robot.side import SideAnyCase

#: Highest frame rate a timeline may have [Hz]; ALMotion's cycle is 50 Hz.
MAX_FRAME_RATE = MAX_RATE


def _check_table(name: str, rows: list[Row], n: int, width: int) -> None:
    if len(rows) != n:
        raise ValueError(f"{name} has {len(rows)} rows, expected {n} (one per time)")
    for i, row in enumerate(rows):
        if len(row) != width:
            raise ValueError(f"{name}[{i}] has {len(row)} values, expected {width}")


class CommandFrames(Message):
    """Joint angles at the frames of a timeline.

    Attributes:
        arm: Which arm.
        rate: Frame rate of the timeline [Hz] (Choregraphe's default is 25).
        joint_names: NAO joint names, shape (n,).
        start: Posture at frame 0, the trajectory's start [rad], shape (n,).
        times: Time of frames 1..m from the start [s], shape (m,); frame k is
            at ``k / rate``.
        positions: Joint angles at those frames [rad], shape (m, n).
    """

    arm: SideAnyCase
    rate: float = Field(ge=MIN_RATE, le=MAX_FRAME_RATE)
    joint_names: list[str] = Field(min_length=1)
    start: list[float]
    times: list[float] = Field(min_length=1)
    positions: list[Row]

    @model_validator(mode="after")
    def _shapes(self) -> CommandFrames:
        width = len(self.joint_names)
        if len(self.start) != width:
            raise ValueError(f"start has {len(self.start)} values, expected {width}")
        _check_table("positions", self.positions, len(self.times), width)
        check_times(self.times, first_above=0.0)
        return self

    @property
    def frame_numbers(self) -> list[int]:
        """Timeline frame number of each frame (``round(time * rate)``), shape (m,)."""
        return [round(t * self.rate) for t in self.times]

    @property
    def duration(self) -> float:
        """Time of the last frame [s]."""
        return self.times[-1]


class JointState(Message):
    """Measured joint angles at one moment of an execution.

    Attributes:
        time: Time from the start of the movement [s].
        joint_names: NAO joint names, shape (n,).
        positions: Measured angles [rad], shape (n,).
    """

    time: float
    joint_names: list[str] = Field(min_length=1)
    positions: list[float]

    @model_validator(mode="after")
    def _shapes(self) -> JointState:
        if len(self.positions) != len(self.joint_names):
            raise ValueError("positions need one value per joint name")
        return self


class ExecutedJointStates(Message):
    """What the robot did: measured angles beside the commanded ones.

    Attributes:
        arm: Which arm.
        joint_names: NAO joint names, shape (n,).
        times: Sample times from the start of the movement [s], shape (k,).
        measured: Angles the robot reported (ALMotion ``getAngles``) [rad], (k, n).
        commanded: The trajectory's angles at ``times - latency`` [rad], (k, n):
            what each measured sample is compared with.
        latency: Delay between a command and the robot reporting it [s]: the
            shift that best aligns measured with commanded (see
            ``bridge.tracking``), the call's ``start_delay`` included.
        start_delay: How long after the call left the robot began it, at
            most [s]: its answer's arrival less its duration (the latency
            searched is at most this plus ``bridge.tracking.MAX_LATENCY``).
        round_trips: Time from each reading's request to its answer [s],
            shape (k,), or empty if the times are exact; a sample's time is
            uncertain by half its round trip.
    """

    arm: SideAnyCase
    joint_names: list[str] = Field(min_length=1)
    times: list[float]
    measured: list[Row]
    commanded: list[Row]
    latency: float = Field(default=0.0, ge=0.0)
    start_delay: float = Field(default=0.0, ge=0.0)
    round_trips: list[NonNegativeFloat] = Field(default_factory=list)

    @model_validator(mode="after")
    def _shapes(self) -> ExecutedJointStates:
        width = len(self.joint_names)
        _check_table("measured", self.measured, len(self.times), width)
        _check_table("commanded", self.commanded, len(self.times), width)
        check_times(self.times, min_step=0.0)
        if self.round_trips and len(self.round_trips) != len(self.times):
            raise ValueError(
                f"round_trips has {len(self.round_trips)} values for "
                f"{len(self.times)} times"
            )
        return self


class TrackingReport(OptionalFieldsMessage):
    """How closely the robot followed the commanded trajectory.

    Attributes:
        joint_names: NAO names of the arm's joints, shape (n,).
        tracking_rms_deg: Root-mean-square of measured minus commanded, per
            joint [deg], once the measurement latency is taken out.
        tracking_max_deg: Largest absolute error, per joint [deg], likewise.
        latency: The delay taken out [s]: the call's trip to the robot,
            sensor cycle and transport, the same for every joint.
        start_delay: How long after the call left the robot began it, at
            most [s] (see ``ExecutedJointStates``); the latency is searched
            up to this plus ``bridge.tracking.MAX_LATENCY``.
        unaligned_rms_deg: The RMS error without taking the latency out [deg].
        samples: Number of measured samples compared.
        discarded: Samples left out because their time was uncertain (their
            reading's round trip was long, see ``bridge.tracking``).
        time_uncertainty: Largest uncertainty of a compared sample's time [s]
            (half its round trip).
        sample_period: Mean time between compared samples [s].
        duration: Time of the last sample from the start [s].
        hand_tracking_rms: For a trajectory that moves the hand, the RMS of
            its measured minus commanded open fraction, latency taken out
            [-]; ``None`` (left out of the JSON) otherwise.
        hand_tracking_max: Its largest absolute error [-], likewise.
    """

    omitted_when_none = ("hand_tracking_rms", "hand_tracking_max")

    joint_names: list[str] = Field(min_length=1)
    tracking_rms_deg: dict[str, float]
    tracking_max_deg: dict[str, float]
    latency: float = Field(default=0.0, ge=0.0)
    start_delay: float = Field(default=0.0, ge=0.0)
    unaligned_rms_deg: dict[str, float] = Field(default_factory=dict)
    samples: int = Field(ge=0)
    discarded: int = Field(default=0, ge=0)
    time_uncertainty: float = Field(default=0.0, ge=0.0)
    sample_period: float = Field(ge=0.0)
    duration: float = Field(ge=0.0)
    hand_tracking_rms: float | None = Field(default=None, ge=0.0)
    hand_tracking_max: float | None = Field(default=None, ge=0.0)


class ExecutionOutcome(OptionalFieldsMessage):
    """How one execution ended (``bridge/outcome``), a stop or an error too.

    The bridge publishes one for every execution it played or tried to play
    (not for a request refused before: busy, a frame over a limit).

    Attributes:
        outcome: ``"completed"`` (played to its last key; its
            :class:`TrackingReport` is on ``bridge/report``), ``"stopped"``
            (the robot ended the movement or released the arm: an
            operator's stop, a rest, the fall manager) or ``"error"``
            (anything else; nothing reported on ``bridge/report``).
        arm: ``"right"`` or ``"left"``.
        duration: The trajectory's length [s].
        error_kind: The typed error's kind (e.g. ``"robot_state"``); None
            (left out) when completed.
        message: The error's message; None (left out) when completed.
        phase: Where it was stopped: ``"approach"`` (the move to the
            trajectory's start; nothing of the trajectory was sent) or
            ``"trajectory"``; None (left out) unless stopped there.
        played: Time into that phase when it was stopped [s]; None (left
            out) unless known.
        phase_duration: That phase's length [s]; None (left out) unless known.
        stopped_by: ``"bridge/stop"`` when a query on that key stopped it
            (the operator's stop through the bridge); None (left out) else.
        stop_reason: The reason that query gave; None (left out) if none.
    """

    omitted_when_none = (
        "error_kind",
        "message",
        "phase",
        "played",
        "phase_duration",
        "stopped_by",
        "stop_reason",
    )

    outcome: Literal["completed", "stopped", "error"]
    arm: str
    duration: float = Field(ge=0.0)
    error_kind: str | None = None
    message: str | None = None
    phase: Literal["approach", "trajectory"] | None = None
    played: float | None = Field(default=None, ge=0.0)
    phase_duration: float | None = Field(default=None, ge=0.0)
    stopped_by: str | None = None
    stop_reason: str | None = None


class ExecuteRequest(Message):
    """Ask the bridge to play a trajectory on the robot.

    Attributes:
        trajectory: The trajectory (the SPEC's trajectory form).
        rate: Frame rate of the command frames [Hz]; ``None`` (or left
            out): the bridge's own (``python -m bridge.serve --rate``, 25).
        approach: Move the arm to the trajectory's start first, slowly, if it
            is elsewhere; if false, a robot away from the start is refused.
    """

    trajectory: Trajectory
    rate: float | None = Field(default=None, ge=MIN_RATE, le=MAX_FRAME_RATE)
    approach: bool = True


class ExecuteReply(Message):
    """The bridge's answer to an :class:`ExecuteRequest`.

    Attributes:
        report: Tracking error per joint.
        states: Measured and commanded angles during the movement.
        frames: Number of command frames sent.
        approach_duration: Length of the move to the start before it [s]
            (0 if the arm was already there).
    """

    report: TrackingReport
    states: ExecutedJointStates
    frames: int = Field(ge=0)
    approach_duration: float = Field(default=0.0, ge=0.0)
