"""Forward and inverse kinematics requests and answers."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import (
    Direction,
    JointVector,
    Message,
    OptionalFieldsMessage,
    Vec3,
)
from shared.messages.measure_params import MeasureParams
from shared.messages.method import Method
from shared.messages.palm_reached import PalmReached
from shared.messages.swivel_goal import SwivelGoal
from shared.robot.side import Side, SideAnyCase


class FKResult(Message):
    """Key points of the arm in the torso frame [m] (the ``armplan fk`` JSON)."""

    shoulder: Vec3
    elbow: Vec3
    wrist: Vec3
    hand: Vec3


class IKRequest(Message):
    """Solve one posture.

    Attributes:
        arm: Which arm (any case: ``"LEFT"`` reads as ``"left"``, as
            ``--arm`` and a ``WristPath`` read it).
        target: Wrist target in the torso frame [m].
        palm: Optional palm direction, unit vector: the wrist turns (its roll
            about the forearm) to face the palm towards it as far as the
            forearm's direction, set by the position task, allows.
        primitive: Primitive to use (``mp`` only); ``None`` lets armplan pick.
        method: ``mp``, ``least-norm`` or ``single``.
        start: Start posture [rad]; ``None`` means the arm hanging at rest.
        swivel: Elbow swivel angle to move to, for the function primitive
            S_R E_P W_R [rad] (pi: elbow straight down, 0: up). Measured
            alike for both arms (``shared.geometry.swivel``), so the left
            arm's mirror of a right-arm swivel phi is 2 pi - phi. Within
            two turns of 0 either way: beyond, it reads as degrees
            (``shared.messages.swivel_goal``).
        measures: Weights of the human performance measures (eq. 17-21).
    """

    arm: SideAnyCase = Side.RIGHT
    target: Vec3
    palm: Direction | None = None
    primitive: str | None = None
    method: Method = Method.MP
    start: JointVector | None = None
    swivel: SwivelGoal | None = None
    measures: MeasureParams = Field(default_factory=MeasureParams)


class IKResult(OptionalFieldsMessage):
    """A solved posture (the ``armplan ik`` JSON).

    Attributes:
        arm: Which arm.
        joints: Joint angles keyed by NAO joint name [rad].
        wrist: Wrist position reached [m].
        target: The target asked for [m].
        error: Distance from wrist to target [m].
        primitive: The primitive whose joints moved (``None`` for baselines).
        method: The method used.
        iterations: Solver iterations spent.
        swivel_goal: The elbow swivel angle asked (S_R E_P W_R) [rad], or
            ``None`` if none was.
        swivel_reached: The elbow swivel angle reached [rad], in [0, 2 pi),
            when one was asked. The elbow is within the solver's position
            tolerance of where the goal puts it; short of that the answer is
            ``SwivelNotReachedError`` instead.
        palm_reached: With a palm direction asked, the palm normal reached
            and its angle from that direction (only the roll about the
            forearm is controlled, so the angle need not be 0); ``None``
            (left out of the JSON) without one.
    """

    omitted_when_none = ("palm_reached",)

    arm: SideAnyCase
    joints: dict[str, float]
    wrist: Vec3
    target: Vec3
    error: float
    primitive: str | None
    method: Method
    iterations: int
    swivel_goal: float | None = None
    swivel_reached: float | None = None
    palm_reached: PalmReached | None = None
