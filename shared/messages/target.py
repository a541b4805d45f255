"""Targets and tasks: what a client asks the planner for."""

from __future__ import annotations

from pydantic import Field, ValidationInfo, field_validator, model_validator

from shared.messages.base import (
    DEFAULT_PLAN_RATE,
    MAX_RATE,
    MIN_PLAN_RATE,
    Direction,
    FieldError,
    JointVector,
    OptionalFieldsMessage,
    Vec3,
)
from shared.messages.hand import HandAction
from shared.messages.measure_params import MeasureParams
from shared.messages.method import Method
from shared.messages.timing_limits import TimingLimits
from shared.messages.wrist_path import WristPath
from shared.robot.side import Side, SideAnyCase

#: Most targets one task may hold.
MAX_TARGETS = 64
#: Most samples a planned trajectory may have: 10 minutes at 100 Hz, both
#: ends included (a 600 s path or segment, the longest, sampled at 100 Hz). A
#: sample takes about 210 bytes of JSON at rest and 340 moving, so above
#: about 49 000 moving samples a trajectory passes the bus's default 16 MiB
#: payload limit: the planner measures those (``check_payload``).
MAX_TRAJECTORY_SAMPLES = 60_001


class ReachTarget(OptionalFieldsMessage):
    """One wrist target of a task.

    Attributes:
        position: Wrist target in the torso frame [m].
        palm: Optional palm direction, torso frame (unit length after
            validation): the wrist rolls about the forearm to turn the palm
            towards it; the forearm's direction comes from the position
            task, so the palm meets it only as far as that roll allows.
        dwell: Time to hold still at the target before the next one [s].
        hand: Optional hand action at the target (``"open"`` or ``"close"``),
            done during the dwell, after arriving and before leaving; a dwell
            shorter than the hand needs is lengthened to its time
            (``services.timing.hand``). ``None`` (left out of the JSON): the
            hand is not commanded.
    """

    omitted_when_none = ("hand",)

    position: Vec3
    palm: Direction | None = None
    dwell: float = Field(default=0.0, ge=0.0, le=60.0)
    hand: HandAction | None = None


class PlanRequest(OptionalFieldsMessage):
    """A task for the planner: reach targets, or follow a timed wrist path.

    Attributes:
        arm: Which arm moves.
        targets: Wrist targets, reached in order (or empty with ``wrist_path``).
        wrist_path: A timed wrist path to follow instead: joint angles at
            exactly its times, no retiming. It is the request's arm's: an
            ``arm`` it names must match, and one it leaves out is ``arm``;
            a request that names no ``arm`` takes the path's.
        start: Start posture [rad]; ``None`` means the arm hanging at rest.
        method: Planning method.
        fastest: Go as fast as a smooth profile along the path allows within
            the limits (not the path's time-optimal timing) instead of at
            human pace.
        rate: Sample rate of the returned trajectory [Hz], ``MIN_PLAN_RATE``
            (16) to ``MAX_RATE`` (1000) (targets only: with a ``wrist_path``,
            100 or left out; ``fastest`` must be false).
        limits: Acceleration and jerk limits to time with (``TimingLimits``:
            up to the bridge's safety net); ``None``: the defaults.
        measures: Weights of the IK's human performance measures (eq.
            17-21); ``None``: the motion model's fitted weights (method
            ``mp``; the baselines, which use no model, the shipped ones).
        request_id: The caller's name for this request (1-64 letters, digits,
            ``_ . -``), or ``None``. The planner answers a request that
            repeats an id it saw recently with the first one's answer,
            planned and published once, so a caller may ask again when an
            answer is late (``Bus.call(..., repeat=True)``).
        path_tolerance: With ``wrist_path``, the farthest the wrist may be
            from a sample of the path at its time [m] (0 < it <= 0.1); a
            path the arm cannot follow that closely is refused
            (``OffPathError``). ``None`` (left out of the JSON): the
            planner's ``PATH_TOLERANCE``, 1 mm.
        other_arm: Where the other arm is held while this one moves [rad],
            its five joints (within its own ranges): the plan keeps clear of
            it as of NAO's body (``shared.robot.body.other_arm``). ``None``
            (left out of the JSON): the planner does not know where it is
            (the robot bridge still keeps clear of it as measured).
    """

    omitted_when_none = ("path_tolerance", "other_arm")

    arm: SideAnyCase = Side.RIGHT
    targets: list[ReachTarget] = Field(default_factory=list, max_length=MAX_TARGETS)
    wrist_path: WristPath | None = None
    start: JointVector | None = None
    method: Method = Method.MP
    fastest: bool = False
    rate: float = Field(default=DEFAULT_PLAN_RATE, le=MAX_RATE)
    limits: TimingLimits | None = None
    measures: MeasureParams | None = None
    request_id: str | None = Field(default=None, pattern=r"^[A-Za-z0-9_.-]{1,64}$")
    path_tolerance: float | None = Field(default=None, gt=0.0, le=0.1)
    other_arm: JointVector | None = None

    @field_validator("rate")
    @classmethod
    def _playable_rate(cls, rate: float) -> float:
        """``rate``, if the robot bridge can play a plan sampled at it."""
        if not rate >= MIN_PLAN_RATE:  # NaN too
            raise ValueError(
                f"{rate:g} Hz is below the {MIN_PLAN_RATE:g} Hz a plan needs: the "
                "robot bridge and armplan export refuse coarser samples, too far "
                "apart to show the movement"
            )
        return rate

    @field_validator("wrist_path")
    @classmethod
    def _path_of_the_arm(
        cls, path: WristPath | None, info: ValidationInfo
    ) -> WristPath | None:
        """``path``, given the request's arm if it names none.

        Its ``arm`` stays unset (``model_fields_set``), so a caller that
        changes the request's arm later (``armplan plan --task --arm``)
        knows the path follows it.
        """
        arm = info.data.get("arm")  # absent if the arm itself was refused
        if path is None or arm is None or "arm" in path.model_fields_set:
            return path
        return WristPath.model_construct(
            path.model_fields_set, **(dict(path) | {"arm": arm})
        )

    @model_validator(mode="after")
    def _one_kind(self) -> PlanRequest:
        if (self.wrist_path is None) == (not self.targets):
            raise FieldError(
                "wrist_path" if self.wrist_path is not None else "targets",
                "give either targets or a wrist_path, not both or neither",
            )
        if self.wrist_path is not None and "arm" not in self.model_fields_set:
            # {"wrist_path": {"arm": "left", ...}} is a left request: naming
            # the arm once, on the path, is enough (it was refused as "for
            # the right arm", the default, even with `armplan plan --arm left`).
            # Frozen: set as pydantic sets it; "arm" stays unset, as given.
            object.__setattr__(self, "arm", self.wrist_path.arm)
        if self.wrist_path is not None and self.wrist_path.arm != self.arm:
            raise FieldError(
                "arm",
                f"wrist_path is for the {self.wrist_path.arm.value} arm, "
                f"the request for the {self.arm.value}",
            )
        if self.wrist_path is not None and (
            self.fastest or self.rate != DEFAULT_PLAN_RATE
        ):
            raise FieldError(  # they were ignored: the path keeps its samples
                "fastest" if self.fastest else "rate",
                "fastest and rate apply to targets only: a wrist_path keeps its "
                "own times (no retiming)",
            )
        if self.path_tolerance is not None and self.wrist_path is None:
            raise FieldError(
                "path_tolerance", "path_tolerance applies to a wrist_path only"
            )
        held = sum(t.dwell for t in self.targets)
        if held * self.rate > MAX_TRAJECTORY_SAMPLES:
            raise FieldError(
                "targets",
                f"the dwells alone ({held:g} s at {self.rate:g} Hz) make "
                f"{held * self.rate:.0f} samples, more than "
                f"{MAX_TRAJECTORY_SAMPLES} (MAX_TRAJECTORY_SAMPLES): shorten the "
                "dwells, split the task or lower the rate",
            )
        return self
