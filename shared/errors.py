"""One root exception, ``ArmplanError``, and the specific failures below it.

Every failure keeps its evidence (the unreachable target, the violated limit)
as attributes, so a caller can act on it, and as a JSON-ready ``evidence``
dict, so the same error can cross Zenoh as a typed ``reply_err`` and be raised
again on the other side with :func:`error_from_wire`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, ClassVar

from shared.text.counted import counted

if TYPE_CHECKING:
    import numpy as np


def _fmt_vec(values: Sequence[float] | np.ndarray) -> str:
    """Format a short vector as ``(0.100, -0.120, 0.050)``."""
    return "(" + ", ".join(f"{float(v):.4g}" for v in values) + ")"


def fixed(value: float, decimals: int) -> str:
    """``value`` with ``decimals`` decimals, or in exponent form if huge (1e308)."""
    return f"{value:.{decimals}f}" if abs(value) < 1e6 else f"{value:.{decimals}g}"


def _decimals_apart(value: float, bounds: tuple[float, float], least: int = 5) -> int:
    """Fewest decimals from ``least`` (up to 12) printing ``value`` unlike ``bounds``.

    A value just outside a range must not read as its bound.
    """
    decimals = least
    while decimals < 12 and any(
        fixed(value, decimals) == f"{bound:.{decimals}f}" for bound in bounds
    ):
        decimals += 1
    return decimals


class ArmplanError(Exception):
    """Root of every error armplan raises on purpose.

    Attributes:
        evidence: JSON-ready facts behind the failure.
    """

    kind: ClassVar[str] = "armplan_error"
    registry: ClassVar[dict[str, type[ArmplanError]]] = {}

    def __init__(self, message: str, **evidence: Any) -> None:
        super().__init__(message)
        self.message = message
        self.evidence = evidence

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:  # a subclass of the same kind leaves it
            ArmplanError.registry[cls.kind] = cls

    def to_wire(self) -> dict[str, Any]:
        """The error as a JSON-ready dict: ``{"kind", "message", "evidence"}``."""
        return {"kind": self.kind, "message": self.message, "evidence": self.evidence}


ArmplanError.registry[ArmplanError.kind] = ArmplanError


class InvalidInputError(ArmplanError):
    """A value given to armplan is malformed, out of its domain or not finite."""

    kind = "invalid_input"

    def __init__(self, message: str, *, field: str = "", **evidence: Any) -> None:
        super().__init__(message, field=field, **evidence)
        self.field = field


class UnknownArmError(InvalidInputError):
    """The arm name is neither ``right`` nor ``left``."""

    kind = "unknown_arm"

    def __init__(self, name: str) -> None:
        super().__init__(
            f"unknown arm {name!r}: expected 'right' or 'left'", field="arm", name=name
        )
        self.name = name


class TooFewSamplesError(InvalidInputError):
    """Too few samples for a fit to mean anything: the fit is refused.

    Attributes:
        found: The samples that count, e.g. those before their trial's end.
        needed: The fewest that give defined estimates.
    """

    kind = "too_few_samples"

    def __init__(self, message: str, *, field: str, found: int, needed: int) -> None:
        super().__init__(message, field=field, found=int(found), needed=int(needed))
        self.found = int(found)
        self.needed = int(needed)


class UnknownPrimitiveError(InvalidInputError):
    """A movement primitive's name is not one of the ten."""

    kind = "unknown_primitive"

    def __init__(self, name: str, known: Sequence[str]) -> None:
        super().__init__(
            f"unknown movement primitive {name!r}; known: " + ", ".join(known),
            field="primitive",
            name=name,
            known=list(known),
        )
        self.name = name


class UnreachableTargetError(ArmplanError):
    """The IK found no posture within the joint limits that puts the wrist there.

    Out of the reach shell no posture can; within it (``residual`` given)
    the solver, restarts included, stopped that far from the target: a
    search it did not make may still find one (one target with a palm the
    solver missed by 138.5 mm has a posture 5.7 mm from it, palm exact).

    Attributes:
        target: Target wrist position in the torso frame [m], shape (3,).
        distance: Distance from the shoulder to the target [m].
        reach: Interval of shoulder-to-wrist distances the arm can make [m].
        at: Where the target came from, e.g. "wrist-path sample 37 (t = ...)".
        palm: The wanted palm direction the posture also had to meet, or
            None. The IK's solver (``services.ik.solve``) raises with a palm
            only from a primitive the caller named (other than the full
            grasp, S_R E_PR W_PR); otherwise a missed target
            with a palm is solved again without it, and the error is either
            that one's (palm None: the target itself is out of reach) or a
            ``PalmRollOutOfRangeError``. Only the palm's roll about the
            forearm is turned towards it, so the message says so, not that
            the palm faces it.
        advice: What to change, after the message (e.g. add samples), or "".
    """

    kind = "unreachable_target"

    def __init__(
        self,
        target: Sequence[float] | np.ndarray,
        *,
        arm: str,
        distance: float,
        reach: tuple[float, float],
        residual: float | None = None,
        at: str = "",
        palm: Sequence[float] | np.ndarray | None = None,
        advice: str = "",
    ) -> None:
        prefix = f"{at}: " if at else ""
        where = (
            f"{prefix}target {_fmt_vec(target)} m is {fixed(distance, 4)} m "
            f"from the {arm} shoulder"
        )
        span = f"the wrist reaches {reach[0]:.4f}..{reach[1]:.4f} m from it"
        if residual is None:
            message = f"{where}; {span}"
        else:
            message = (
                f"{where} ({span}) but the IK solver stopped "
                f"{residual * 1000:.1f} mm from it"
            )
            if palm is not None:
                message += f" with the palm's roll turned towards {_fmt_vec(palm)}"
        if advice:
            message += f": {advice}"
        self._with_reach(
            message,
            target,
            arm=arm,
            distance=distance,
            reach=reach,
            residual=residual,
            at=at,
            palm=palm,
            advice=advice,
        )

    def _with_reach(
        self,
        message: str,
        target: Sequence[float] | np.ndarray,
        *,
        arm: str,
        distance: float,
        reach: tuple[float, float],
        residual: float | None,
        at: str,
        palm: Sequence[float] | np.ndarray | None,
        advice: str,
        **more: Any,
    ) -> None:
        """The root's init with the facts every kind of this error carries.

        ``more``: a kind's own facts, added to the evidence.
        """
        ArmplanError.__init__(
            self,
            message,
            target=[float(v) for v in target],
            arm=arm,
            distance=float(distance),
            reach=[float(reach[0]), float(reach[1])],
            residual=None if residual is None else float(residual),
            at=at,
            palm=None if palm is None else [float(v) for v in palm],
            advice=advice,
            **more,
        )
        self.target = tuple(float(v) for v in target)
        self.distance = float(distance)
        self.reach = (float(reach[0]), float(reach[1]))
        self.residual = None if residual is None else float(residual)


class TargetInBodyError(UnreachableTargetError):
    """The target lies in NAO's own body, or nearer it than the hand may come.

    Whatever the posture, the hand's end at the wrist (a ball of the hand's
    radius) would be less than the body model's margin from a body part
    (``shared.robot.body``). Read as out of reach: every ``UnreachableTargetError``
    attribute is there (no residual, no palm).

    Attributes:
        body_part: ``"torso"``, ``"pelvis"`` or ``"head"``; or the other
            arm's part (``"left forearm"``) where a plan request gives it.
        clearance: Distance between the hand's surface and the part's [m];
            negative: that deep inside it.
        margin: The least distance kept [m].
        inside: The target itself lies in the body part.
    """

    kind = "target_in_body"

    def __init__(
        self,
        target: Sequence[float] | np.ndarray,
        *,
        arm: str,
        distance: float,
        reach: tuple[float, float],
        body_part: str,
        clearance: float,
        margin: float,
        at: str = "",
        inside: bool = False,
    ) -> None:
        prefix = f"{at}: " if at else ""
        deep = -clearance * 1000
        if inside:
            how = (
                f"inside NAO's {body_part}: the {arm} hand there would be "
                f"{deep:.1f} mm in it"
            )
        elif clearance < 0:
            how = (
                f"too near NAO's {body_part}: the {arm} hand there would be "
                f"{deep:.1f} mm inside it"
            )
        else:
            how = (
                f"{clearance * 1000:.1f} mm from NAO's {body_part} for the {arm} "
                f"hand, nearer than the {margin * 1000:.1f} mm kept clear"
            )
        kept = (
            "the torso, pelvis and head"
            if body_part in ("torso", "pelvis", "head")
            else "the other arm where the request holds it"
        )
        self._with_reach(
            f"{prefix}target {_fmt_vec(target)} m is {how}; the arm keeps clear "
            f"of {kept} (docs/robot.md, 'NAO's own body')",
            target,
            arm=arm,
            distance=distance,
            reach=reach,
            residual=None,
            at=at,
            palm=None,
            advice="",
            body_part=body_part,
            clearance=float(clearance),
            margin=float(margin),
            inside=bool(inside),
        )
        self.body_part = body_part
        self.clearance = float(clearance)
        self.margin = float(margin)
        self.inside = bool(inside)


class PalmRollOutOfRangeError(UnreachableTargetError):
    """The target is reached, but no roll within WristYaw's range faces the palm.

    The IK turns the palm by its roll about the forearm, NAO's WristYaw. A
    posture that reaches the target without the palm was found, and the roll
    that would face the palm there lies outside WristYaw's range. Read as
    out of reach with that palm: every ``UnreachableTargetError`` attribute is
    there (the residual is the posture's, within the IK's tolerance).

    Attributes:
        palm: The palm direction asked (unit).
        wrist_yaw: The WristYaw the roll needs there [rad] (nearest the range).
        wrist_yaw_range: WristYaw's range [rad].
        posture: The posture that reaches the target [rad], 5 values.
        nearest_angle: Angle between the palm and ``palm`` with WristYaw at
            the bound nearest the roll needed [rad].
    """

    kind = "palm_roll_out_of_range"

    def __init__(
        self,
        target: Sequence[float] | np.ndarray,
        *,
        arm: str,
        distance: float,
        reach: tuple[float, float],
        residual: float,
        palm: Sequence[float] | np.ndarray,
        wrist_yaw: float,
        wrist_yaw_range: tuple[float, float],
        posture: Sequence[float] | np.ndarray,
        nearest_angle: float,
    ) -> None:
        low, high = wrist_yaw_range
        self._with_reach(
            f"target {_fmt_vec(target)} m is within the {arm} arm's reach, but "
            f"the palm cannot be turned towards {_fmt_vec(palm)} there: in the "
            f"posture that reaches it, {_fmt_vec(posture)} rad, the roll about "
            f"the forearm that faces the palm needs WristYaw = {wrist_yaw:.3f} "
            f"rad, outside its range {low:.3f}..{high:.3f} rad (with WristYaw at "
            f"its nearest bound the palm is {math.degrees(nearest_angle):.1f} deg "
            "from that direction); give another palm direction, or none",
            target,
            arm=arm,
            distance=distance,
            reach=reach,
            residual=residual,
            at="",
            palm=palm,
            advice="",
            wrist_yaw=float(wrist_yaw),
            wrist_yaw_range=[float(low), float(high)],
            posture=[float(v) for v in posture],
            nearest_angle=float(nearest_angle),
        )
        self.palm = tuple(float(v) for v in palm)
        self.wrist_yaw = float(wrist_yaw)
        self.wrist_yaw_range = (float(low), float(high))
        self.posture = tuple(float(v) for v in posture)
        self.nearest_angle = float(nearest_angle)


class BodyCollisionError(ArmplanError):
    """A posture of a plan, or its start, brings the arm into NAO's own body.

    Attributes:
        arm: ``"right"`` or ``"left"``.
        arm_part: ``"upper arm"``, ``"forearm"`` or ``"hand"``.
        body_part: ``"torso"``, ``"pelvis"`` or ``"head"``; or the other
            arm's part (``"left forearm"``) where a plan request gives it.
        clearance: Distance between their surfaces [m]; negative: overlap.
        margin: The least distance kept [m].
        index: The first sample (of the trajectory) nearer than ``margin``;
            0 for a start posture.
        time: Its time from the start [s].
    """

    kind = "body_collision"

    def __init__(
        self,
        *,
        arm: str,
        arm_part: str,
        body_part: str,
        clearance: float,
        margin: float,
        index: int,
        time: float,
        what: str = "the planned movement",
        at: str | None = None,
        advice: str = (
            "the plan is refused: choose targets the arm reaches without "
            "crossing the body"
        ),
    ) -> None:
        where = f" at sample {index} (t = {time:.3f} s)" if at is None else at
        super().__init__(
            f"{what} brings the {arm} {arm_part} {body_words(clearance, margin)} "
            f"NAO's {body_part}{where}; {advice} (docs/robot.md, 'NAO's own body')",
            arm=arm,
            arm_part=arm_part,
            body_part=body_part,
            clearance=float(clearance),
            margin=float(margin),
            index=int(index),
            time=float(time),
        )
        self.arm = arm
        self.arm_part = arm_part
        self.body_part = body_part
        self.clearance = float(clearance)
        self.margin = float(margin)
        self.index = int(index)
        self.time = float(time)


def body_words(clearance: float, margin: float) -> str:
    """How near an arm part is to a body part, ending before the part's name.

    E.g. "12.3 mm into" or "3.1 mm (less than the 5.0 mm kept) from".
    """
    if clearance < 0:
        return f"{-clearance * 1000:.1f} mm into"
    return f"{clearance * 1000:.1f} mm (less than the {margin * 1000:.1f} mm kept) from"


class OffPathError(ArmplanError):
    """The arm cannot follow a timed wrist path within the tolerance.

    Attributes:
        index: The sample whose wrist is farthest from the path.
        time: Its time [s].
        deviation: Its wrist's distance from the path's sample [m].
        tolerance: The largest distance allowed [m].
    """

    kind = "off_path"

    def __init__(
        self,
        *,
        arm: str,
        index: int,
        time: float,
        deviation: float,
        tolerance: float,
        reason: str = "",
    ) -> None:
        why = f" ({reason})" if reason else ""
        super().__init__(
            f"the {arm} arm cannot follow the wrist path: at sample {index} "
            f"(t = {time:.3f} s) its wrist is {deviation * 1000:.2f} mm from the "
            f"path, more than the tolerance {tolerance * 1000:.2f} mm{why}",
            arm=arm,
            index=int(index),
            time=float(time),
            deviation=float(deviation),
            tolerance=float(tolerance),
            reason=reason,
        )
        self.index = int(index)
        self.time = float(time)
        self.deviation = float(deviation)
        self.tolerance = float(tolerance)


class PrimitiveCannotReachError(ArmplanError):
    """The chosen primitive's active joints cannot put the wrist on the target.

    Attributes:
        primitive: The primitive's name, e.g. ``"E_R W_P"``.
        target: Target wrist position [m], shape (3,).
        nearest: The closest wrist position the primitive reaches [m], shape (3,).
        residual: Distance from ``nearest`` to ``target`` [m].
    """

    kind = "primitive_cannot_reach"

    def __init__(
        self,
        primitive: str,
        target: Sequence[float] | np.ndarray,
        nearest: Sequence[float] | np.ndarray,
        residual: float,
        reason: str,
    ) -> None:
        super().__init__(
            f"primitive {primitive!r} cannot reach target {_fmt_vec(target)} m: "
            f"{reason}; closest wrist position {_fmt_vec(nearest)} m is "
            f"{residual * 1000:.1f} mm away",
            primitive=primitive,
            target=[float(v) for v in target],
            nearest=[float(v) for v in nearest],
            residual=float(residual),
            reason=reason,
        )
        self.primitive = primitive
        self.target = tuple(float(v) for v in target)
        self.nearest = tuple(float(v) for v in nearest)
        self.residual = float(residual)


class SwivelNotReachedError(ArmplanError):
    """S_R E_P W_R held the wrist but swivelled the elbow short of the goal.

    The posture reached travels with the error (``joints``), so a caller
    that can use the nearest swivel still has it.

    Attributes:
        goal: The swivel angle asked [rad].
        reached: The swivel angle reached [rad], in [0, 2 pi).
        shortfall: ``reached - goal`` wrapped into [-pi, pi) [rad].
        elbow_miss: Distance of the elbow from where the goal puts it [m].
        joint: NAO name of the joint on its limit, or ``""`` if none is.
        limit: That joint's limit [rad], or ``None``.
        joints: The posture reached, keyed by NAO joint name [rad].
    """

    kind = "swivel_not_reached"

    def __init__(
        self,
        goal: float,
        reached: float,
        *,
        shortfall: float,
        elbow_miss: float,
        joints: dict[str, float],
        joint: str = "",
        limit: float | None = None,
    ) -> None:
        if joint and limit is not None:
            why = f"{joint} is on its limit {limit:.5f} rad"
        else:
            why = "no joint is on a limit (the solver stopped there)"
        super().__init__(
            f"elbow swivel {goal:.4f} rad not reached: the elbow stopped at "
            f"{reached:.4f} rad, {math.degrees(abs(shortfall)):.1f} deg short and "
            f"{elbow_miss * 1000:.1f} mm from where the goal puts it; {why}",
            goal=float(goal),
            reached=float(reached),
            shortfall=float(shortfall),
            elbow_miss=float(elbow_miss),
            joint=joint,
            limit=None if limit is None else float(limit),
            joints={name: float(v) for name, v in joints.items()},
        )
        self.goal = float(goal)
        self.reached = float(reached)
        self.shortfall = float(shortfall)
        self.elbow_miss = float(elbow_miss)
        self.joint = joint
        self.limit = None if limit is None else float(limit)
        self.joints = dict(joints)


class JointLimitError(ArmplanError):
    """A joint angle lies outside its range.

    Attributes:
        joint: NAO joint name.
        value: The offending angle [rad].
        lower: Lower limit [rad].
        upper: Upper limit [rad].
    """

    kind = "joint_limit"

    def __init__(
        self,
        joint: str,
        value: float,
        lower: float,
        upper: float,
        where: str = "",
        hint: str = "",
    ) -> None:
        at = f" {where}" if where else ""
        n = _decimals_apart(value, (lower, upper))
        super().__init__(
            f"{joint} = {fixed(value, n)} rad{at} is outside its range "
            f"[{lower:.{n}f}, {upper:.{n}f}] rad{hint}",
            joint=joint,
            value=float(value),
            lower=float(lower),
            upper=float(upper),
            where=where,
        )
        self.joint = joint
        self.value = float(value)
        self.lower = float(lower)
        self.upper = float(upper)


class LimitViolationError(ArmplanError):
    """A trajectory sample exceeds a speed, acceleration or jerk limit.

    Attributes:
        joint: NAO joint name.
        quantity: ``"velocity"``, ``"acceleration"`` or ``"jerk"``.
        value: The offending magnitude [rad/s, rad/s^2 or rad/s^3].
        limit: The limit it exceeds, same unit.
        index: Index of the sample.
        time: Time of the sample [s].
        context: Why the sample asks that much, if not plain (e.g. to stop
            at the end), shown in brackets after the limit.
        advice: What to do about it, if said (after a semicolon).
    """

    kind = "limit_violation"
    _units: ClassVar[dict[str, str]] = {
        "position": "rad",
        "velocity": "rad/s",
        "acceleration": "rad/s^2",
        "jerk": "rad/s^3",
    }

    def __init__(
        self,
        joint: str,
        quantity: str,
        value: float,
        limit: float,
        index: int,
        time: float,
        *,
        context: str = "",
        advice: str = "",
    ) -> None:
        unit = self._units.get(quantity, "")
        why = f" ({context})" if context else ""
        then = f"; {advice}" if advice else ""
        super().__init__(
            f"{joint} {quantity} {value:.4g} {unit} at sample {index} "
            f"(t = {time:.3f} s) exceeds its limit {limit:.4g} {unit}{why}{then}",
            joint=joint,
            quantity=quantity,
            value=float(value),
            limit=float(limit),
            index=int(index),
            time=float(time),
            context=context,
            advice=advice,
        )
        self.joint = joint
        self.quantity = quantity
        self.value = float(value)
        self.limit = float(limit)
        self.index = int(index)
        self.time = float(time)
        self.context = context
        self.advice = advice

    def advised(self, advice: str) -> LimitViolationError:
        """The same violation, saying ``advice`` (what to do about it)."""
        return LimitViolationError(
            self.joint,
            self.quantity,
            self.value,
            self.limit,
            self.index,
            self.time,
            context=self.context,
            advice=advice,
        )


class RecordingError(ArmplanError):
    """An MCAP file cannot be written or read (missing, empty, truncated, corrupt).

    Attributes:
        path: The file.
        readable: Messages that could be read before the problem, if known.
    """

    kind = "recording_error"

    def __init__(self, message: str, *, path: str, readable: int | None = None) -> None:
        super().__init__(message, path=path, readable=readable)
        self.path = path
        self.readable = readable


class ServiceAppearedError(ArmplanError):
    """Base: a service came alive during a replay sending what it would take.

    The replay stopped: nothing more was sent. A subclass names the
    service and what the held-back messages would have done to it.

    Attributes:
        namespace: The replay's namespace.
        sent: Messages sent before it stopped.
        total: Messages the replay would have sent.
        held: Each key the service takes with messages left unsent -> how
            many (empty if every one had been sent: the rest is other keys).
    """

    #: Who came alive, e.g. "a bridge".
    who: ClassVar[str]
    #: The keys it takes, e.g. "plan/* and bridge/*".
    takes: ClassVar[str]

    def __init__(
        self, *, namespace: str, sent: int, total: int, held: dict[str, int]
    ) -> None:
        kept = ", ".join(f"{key} ({n} left)" for key, n in held.items())
        stopped = (
            f"{self.who} came alive in namespace {namespace!r} during the replay: "
            f"it stopped after {sent} of {counted(total, 'message')}, holding back "
            "the "
        )
        super().__init__(
            f"{stopped}recorded {kept} {self._harm(held)}"
            if held
            else f"{stopped}other {total - sent}; every recorded {self.takes} "
            "message had been sent before it came alive. To replay the rest, "
            "choose its keys with --keys",
            namespace=namespace,
            sent=sent,
            total=total,
            held=held,
        )
        self.namespace = namespace
        self.sent = sent
        self.total = total
        self.held = held

    def _harm(self, held: dict[str, int]) -> str:
        """What the ``held`` messages would have done, and how to send them."""
        raise NotImplementedError


class BridgeAppearedError(ServiceAppearedError):
    """A bridge came alive in the namespace during a replay of every key.

    The rest of its ``plan/*`` and ``bridge/*`` messages would have gone to
    the bridge (one with ``--follow`` plays each trajectory on the robot)
    and mixed with the live ones.
    """

    kind = "bridge_appeared"
    who = "a bridge"
    takes = "plan/* and bridge/*"

    def _harm(self, held: dict[str, int]) -> str:
        return (
            "(a bridge with --follow would move the robot again, and they would "
            "mix with the live messages); a message already on its way when the "
            "bridge was seen cannot be recalled. To replay into a live robot on "
            "purpose, choose the keys with --keys, e.g. --keys plan/trajectory "
            "--wait-for bridge"
        )


class DecideAppearedError(ServiceAppearedError):
    """A decide service came alive during a replay of recorded models.

    The rest of its ``fit/*`` messages (the fit service's
    ``fit/model/update``) would have replaced the model the new decide
    service decides with.
    """

    kind = "decide_appeared"
    who = "a decide service"
    takes = "fit/*"

    def _harm(self, held: dict[str, int]) -> str:
        return (
            "(it would replace the model the decide service decides with, for "
            "every later plan); a message already on its way when the service "
            "was seen cannot be recalled. To replay it on purpose, choose the "
            f"keys with --keys, e.g. --keys {next(iter(held))}"
        )


class RemoteError(ArmplanError):
    """An error a remote armplan process reported, of a kind this side lacks."""

    kind = "remote_error"


class TimingError(ArmplanError):
    """The time parameterisation found no timing within the limits.

    Ruckig found no profile, or the sampled trajectory still broke a limit
    after the allowed retries. ``evidence`` holds what was asked and why.
    """

    kind = "timing_error"


class ModelChangedError(ArmplanError):
    """A plan's decisions came from more than one motion model, twice running.

    The planner asks the decide stage once per reach; a model swapped in
    meanwhile (a fit landing) splits the plan between two models. It plans
    once more; this is raised if that plan is split as well.

    Attributes:
        models: The digests of the models, one per decision (``None``: not
            known), of the last plan.
    """

    kind = "model_changed"

    def __init__(self, models: list[str | None]) -> None:
        distinct = list(dict.fromkeys(m for m in models if m is not None))
        super().__init__(
            f"the motion model changed while planning, twice running (its "
            f"decisions came from models {', '.join(distinct)}): the fit "
            "service is swapping models in; ask again",
            models=models,
        )
        self.models = models


def error_from_wire(payload: dict[str, Any]) -> ArmplanError:
    """Rebuild an error sent with :meth:`ArmplanError.to_wire`.

    The result has the sender's kind, message and evidence; its class is the
    registered class for that kind (or :class:`RemoteError` if unknown), built
    without running that class's own constructor.
    """
    kind = str(payload.get("kind", RemoteError.kind))
    message = str(payload.get("message", "remote error without a message"))
    evidence = payload.get("evidence") or {}
    cls = ArmplanError.registry.get(kind, RemoteError)
    error = cls.__new__(cls)
    ArmplanError.__init__(error, message, **dict(evidence))
    for name, value in dict(evidence).items():
        if not hasattr(error, name):
            setattr(error, name, value)
    return error


# Errors of the Zenoh services (shared/bus): each names the service and key.


class ServiceUnavailableError(ArmplanError):
    """A service a request needs is not running (no liveliness token, no router).

    Attributes:
        service: The missing service, e.g. ``"ik"`` (``"router"`` if no router).
        key: The key expression the request was for, if any.
        reason: What showed it was missing.
        elsewhere: The other namespaces where a missing service is alive on
            the same router, by service (``{"bridge": ["lab1"]}``; ``{}``:
            none seen, or not asked). ``reason`` says so too.
    """

    kind = "service_unavailable"

    def __init__(
        self,
        service: str,
        *,
        key: str = "",
        reason: str = "",
        elsewhere: dict[str, list[str]] | None = None,
    ) -> None:
        at = f" for {key}" if key else ""
        why = f": {reason}" if reason else ""
        found = {name: list(spaces) for name, spaces in (elsewhere or {}).items()}
        super().__init__(
            f"service {service!r} is unavailable{at}{why}",
            service=service,
            key=key,
            reason=reason,
            elsewhere=found,
        )
        self.service = service
        self.key = key
        self.reason = reason
        self.elsewhere = found


class RequestTimeoutError(ArmplanError):
    """A service did not answer a request within its timeout.

    Attributes:
        service: The service asked, e.g. ``"ik"``.
        key: The key expression queried.
        timeout: How long the caller waited [s].
    """

    kind = "request_timeout"

    def __init__(
        self, service: str, *, key: str, timeout: float, message: str | None = None
    ) -> None:
        """``message``: what happened, if not the caller's own wait that ran out."""
        super().__init__(
            message
            or f"service {service!r} did not answer {key} within {timeout:.3f} s",
            service=service,
            key=key,
            timeout=float(timeout),
        )
        self.service = service
        self.key = key
        self.timeout = float(timeout)


class PayloadTooLargeError(InvalidInputError):
    """A request's payload exceeds the configured size limit.

    Attributes:
        size: The payload's size [bytes].
        limit: The largest payload accepted [bytes].
        key: The key expression it was sent to.
    """

    kind = "payload_too_large"

    def __init__(self, *, size: int, limit: int, key: str) -> None:
        super().__init__(
            f"payload of {size} bytes for {key} exceeds the limit of {limit} bytes",
            field="payload",
            size=int(size),
            limit=int(limit),
            key=key,
        )
        self.size = int(size)
        self.limit = int(limit)
        self.key = key


class InternalServiceError(ArmplanError):
    """A service failed in an unexpected way; it logged the traceback and runs on.

    Attributes:
        service: The service that failed.
        key: The key expression of the request.
        error_type: The unexpected exception's class name.
        detail: The unexpected exception's message.
    """

    kind = "internal_error"

    def __init__(self, service: str, *, key: str, error_type: str, detail: str) -> None:
        super().__init__(
            f"service {service!r} failed on {key} with an unexpected {error_type}: "
            f"{detail} (the service keeps running; see its log)",
            service=service,
            key=key,
            error_type=error_type,
            detail=detail,
        )
        self.service = service
        self.key = key
        self.error_type = error_type
        self.detail = detail


class ServiceBusyError(ArmplanError):
    """A service's request queue is full; the request was refused, not dropped.

    Attributes:
        service: The busy service.
        key: The key expression of the refused request.
        queued: Requests waiting when it was refused.
    """

    kind = "service_busy"

    def __init__(
        self, service: str, *, key: str, queued: int, why: str | None = None
    ) -> None:
        """``why``: what keeps it busy (default: the ``queued`` requests waiting)."""
        busy = why or f"{queued} requests are already waiting"
        super().__init__(
            f"service {service!r} refused {key}: {busy}; try again later",
            service=service,
            key=key,
            queued=int(queued),
        )
        self.service = service
        self.key = key
        self.queued = int(queued)


class ServiceRunningError(ArmplanError):
    """A service that must run once per namespace found itself running already.

    Two bridges in one namespace would both play every request on the robot
    (a queryable's answer fans out to all of them); the caller would get one
    answer, perhaps the loser's error, while the arm moves.

    Attributes:
        service: The service, e.g. ``"bridge"``.
        key: The liveliness key another process holds.
    """

    kind = "service_running"

    def __init__(self, service: str, *, key: str, why: str) -> None:
        super().__init__(
            f"service {service!r} is already running ({key} is held by another "
            f"process): {why}; stop the other one first, or use another namespace",
            service=service,
            key=key,
        )
        self.service = service
        self.key = key


class BusConfigError(ArmplanError):
    """The Zenoh configuration (file or option) is malformed or unsafe.

    Attributes:
        source: The file or command-line option it came from.
        setting: The setting that is wrong, e.g. ``"scouting/multicast/enabled"``.
    """

    kind = "bus_config"

    def __init__(self, problem: str, *, source: str, setting: str = "") -> None:
        what = f" ({setting})" if setting else ""
        super().__init__(
            f"Zenoh configuration {source}{what}: {problem}",
            source=source,
            setting=setting,
        )
        self.source = source
        self.setting = setting


class WrongLoginError(BusConfigError):
    """A process's configuration logs in as another process's user.

    The secured router lets each user do its own process's part only: with
    another user's file a process would connect, yet be cut off silently.

    Attributes:
        expected: The process's own user, e.g. ``"bridge"``.
        given: The user the file logs in as, e.g. ``"client"``.
    """

    kind = "wrong_login"

    def __init__(self, *, source: str, expected: str, given: str) -> None:
        super().__init__(
            f"logs in as user {given!r}, but this is the {expected} process, "
            f"which must log in as {expected!r}: give it {expected}'s own file "
            f"({expected}.json5 of the `armplan certs` folder); the secured "
            "router lets each user do only its own process's part",
            source=source,
            setting="transport/auth/usrpwd/user",
        )
        self.evidence.update(expected=expected, given=given)
        self.expected = expected
        self.given = given


# Errors of the robot bridge (bridge/) and the robot it talks to over NAOqi.


class TrajectoryRefusedError(ArmplanError):
    """The bridge refused a whole trajectory before sending any of it to the robot.

    Attributes:
        joint: NAO joint name, e.g. ``RShoulderPitch``.
        quantity: ``"position"``, ``"velocity"``, ``"acceleration"``,
            ``"jerk"``, ``"start"`` (the arm is away from the start and
            the approach move is off), ``"frame_rate"`` (the lines between
            frames stray from the trajectory; value and limit are that gap)
            or ``"velocities"`` (they disagree with the positions: the curve
            through them strays from the positions'; value and limit are
            that gap, ``frame`` the trajectory's sample).
        value: The offending value [rad, rad/s, rad/s^2 or rad/s^3].
        limit: The limit it breaks, same unit (the bound crossed, for a position).
        frame: Index of the command frame (1 is the first key; 0 is the start),
            or of the trajectory's sample for a sample's position or velocity.
        time: Time of that frame (or sample) from the trajectory's start [s].
        detail: What is wrong, after the joint's name.
    """

    kind = "trajectory_refused"

    def __init__(
        self,
        joint: str,
        quantity: str,
        value: float,
        limit: float,
        *,
        frame: int,
        time: float,
        detail: str,
        outcome: str = "nothing was sent",
    ) -> None:
        super().__init__(
            f"trajectory refused, {outcome}: {joint} {detail}",
            joint=joint,
            quantity=quantity,
            value=float(value),
            limit=float(limit),
            frame=int(frame),
            time=float(time),
        )
        self.joint = joint
        self.quantity = quantity
        self.value = float(value)
        self.limit = float(limit)
        self.frame = int(frame)
        self.time = float(time)
        self.detail = detail
        self.outcome = outcome

    def instead(self, outcome: str) -> TrajectoryRefusedError:
        """The same refusal, saying ``outcome`` (e.g. "nothing was written")."""
        return self._with(self.detail, outcome)

    def adding(self, words: str) -> TrajectoryRefusedError:
        """The same refusal with ``words`` after its detail (e.g. a rate to try)."""
        return self._with(self.detail + words, self.outcome)

    def _with(self, detail: str, outcome: str) -> TrajectoryRefusedError:
        return TrajectoryRefusedError(
            self.joint,
            self.quantity,
            self.value,
            self.limit,
            frame=self.frame,
            time=self.time,
            detail=detail,
            outcome=outcome,
        )


class RobotUnavailableError(ArmplanError):
    """The robot (a NAO or the simulated one) cannot be reached or stopped answering.

    Attributes:
        url: The robot's NAOqi address, e.g. ``tcp://127.0.0.1:9559``.
        reason: What showed it, e.g. ``"Connection refused"``.
        elapsed: Time into the running command when it was lost [s], if any.
    """

    kind = "robot_unavailable"

    def __init__(self, url: str, reason: str, *, elapsed: float | None = None) -> None:
        during = "" if elapsed is None else f" {elapsed:.2f} s into the movement"
        super().__init__(
            f"the robot at {url} is unavailable{during}: {reason}",
            url=url,
            reason=reason,
            elapsed=None if elapsed is None else float(elapsed),
        )
        self.url = url
        self.reason = reason
        self.elapsed = None if elapsed is None else float(elapsed)


class RobotBusyError(ArmplanError):
    """The robot is playing another trajectory; this one was refused, not queued.

    A queued movement would start whenever the one before ends, perhaps long
    after its caller gave up waiting: a robot must not move on a stale
    command. An arm found moving by a command the bridge did not send (or
    one still running after the robot was out of reach) is busy too: a move
    started from a moving arm would jerk it.

    Attributes:
        url: The robot's NAOqi address.
        remaining: About how long the playing trajectory still runs [s], or
            ``None`` if not known (the arm was found moving, or its joints
            held by a motion task).
    """

    kind = "robot_busy"

    def __init__(
        self, url: str, remaining: float | None, moving: str | None = None
    ) -> None:
        """The message names ``remaining`` [s], or ``moving``, or neither.

        ``moving``: what the robot was found doing, if not the default for
        ``remaining`` None (an arm still moving, or held by a motion task).
        """
        if moving is not None:
            what = moving
        elif remaining is None:
            what = "has an arm still moving, or held by a motion task (a command "
            what += "not sent by this bridge, or one that went on while the robot "
            what += "was out of reach)"
        else:
            what = f"is playing another trajectory (about {remaining:.1f} s left)"
        done = "has stopped" if remaining is None else "is done"
        super().__init__(
            f"the robot at {url} {what}; nothing was sent: send this one when it "
            f"{done}",
            url=url,
            remaining=None if remaining is None else float(remaining),
        )
        self.url = url
        self.remaining = None if remaining is None else float(remaining)


class CallerDeadlineError(ArmplanError):
    """The caller stops waiting before the movement would end: it is not started.

    A robot must not start a movement its caller has given up on, or will
    before it ends: its reply would come to no one, and a retry would find
    the robot busy. The bridge checks before contacting the robot (the
    trajectory alone), before the approach (both) and again just before the
    trajectory's frames are sent (an approach that took longer).

    Attributes:
        url: The robot's NAOqi address.
        left: The caller's time left when checked [s] (less the time the
            answer needs to travel back).
        approach: The approach move's length [s]; ``None`` if not yet known
            (the arm not yet read), 0 if none is needed or it was played.
        duration: The trajectory's length [s].
        outcome: What became of the movement, e.g. ``"nothing was sent"``.
        overhead: The time counted for the call's way to the robot and the
            answer's making [s].
    """

    kind = "caller_deadline"

    def __init__(
        self,
        url: str,
        left: float,
        approach: float | None,
        duration: float,
        *,
        outcome: str,
        overhead: float = 0.0,
    ) -> None:
        """See the class's attributes; ``overhead`` is named when over 0."""
        if approach is None:
            needs = f"the {duration:.2f} s trajectory alone"
        elif approach > 0.0:
            needs = f"{approach:.2f} s approach + {duration:.2f} s trajectory"
        else:
            needs = f"the {duration:.2f} s trajectory"
        if overhead > 0.0:
            needs += f" + {overhead:.2f} s for the call's way and the answer"
        super().__init__(
            f"the robot at {url}: the caller stops waiting in {max(left, 0.0):.2f} "
            f"s, before the movement would end ({needs}); {outcome}: ask with a "
            "timeout that covers the approach and the trajectory",
            url=url,
            left=float(left),
            approach=None if approach is None else float(approach),
            duration=float(duration),
            outcome=outcome,
            overhead=float(overhead),
        )
        self.url = url
        self.left = float(left)
        self.approach = None if approach is None else float(approach)
        self.duration = float(duration)
        self.outcome = outcome
        self.overhead = float(overhead)


class CallerGoneError(CallerDeadlineError):
    """The caller's session ended before the trajectory: it is not played.

    Its process was interrupted (Ctrl-C) or killed while it waited: its
    caller token went (``shared.bus.gone_callers``). Told apart from a
    deadline by its message alone: the same kind, ``caller_deadline``, and
    the same evidence (``left`` 0), so that read from the wire it has every
    attribute of a :class:`CallerDeadlineError`.

    Attributes:
        url: The robot's NAOqi address.
        left: 0 [s]: the caller waits no more.
        approach: The approach move's length [s]; ``None`` if not yet
            known, 0 if none is needed or it was played.
        duration: The trajectory's length [s].
        outcome: What became of the movement, e.g. ``"nothing was sent"``.
        overhead: The time counted for the call's way to the robot and the
            answer's making [s].
    """

    def __init__(
        self,
        url: str,
        approach: float | None,
        duration: float,
        *,
        outcome: str,
        overhead: float = 0.0,
    ) -> None:
        """See the class's attributes."""
        ArmplanError.__init__(
            self,
            f"the robot at {url}: the caller's session ended (interrupted or "
            f"killed) before the trajectory was played; {outcome}",
            url=url,
            left=0.0,
            approach=None if approach is None else float(approach),
            duration=float(duration),
            outcome=outcome,
            overhead=float(overhead),
        )
        self.url = url
        self.left = 0.0
        self.approach = None if approach is None else float(approach)
        self.duration = float(duration)
        self.outcome = outcome
        self.overhead = float(overhead)


class RobotCommandError(ArmplanError):
    """The robot answered, but refused or failed a command.

    Attributes:
        url: The robot's NAOqi address.
        method: The ALMotion method called, e.g. ``angleInterpolation``.
        reason: The robot's own explanation.
    """

    kind = "robot_command_refused"

    def __init__(self, url: str, method: str, reason: str) -> None:
        super().__init__(
            f"the robot at {url} refused {method}: {reason}",
            url=url,
            method=method,
            reason=reason,
        )
        self.url = url
        self.method = method
        self.reason = reason


class RobotStateError(ArmplanError):
    """The robot was not fit to play the trajectory, or stopped being so during it.

    Not awake, an arm whose stiffness dropped during the movement, a motion
    task the robot ended before its last key, an arm that did not reach the
    trajectory's start: what the robot did is not what the bridge sent.

    Attributes:
        url: The robot's NAOqi address.
        reason: What was found, e.g. ``"the stiffness of RArm dropped during
            the movement"``.
        outcome: What became of the trajectory, e.g. ``"nothing was sent"``.
        stopped: The robot stopped or released the arm during a movement
            (its motion task killed, its stiffness cut): an operator's stop
            looks like this, so the bridge's follower drops what was queued
            before it. False for a robot found unfit before anything moved.
        stopped_at: When the bridge saw the stop [s, ``time.monotonic``, this
            process's clock]; None if not stopped. Not sent over the bus.
    """

    kind = "robot_state"

    def __init__(
        self,
        url: str,
        reason: str,
        *,
        outcome: str,
        stopped_at: float | None = None,
        **evidence: Any,
    ) -> None:
        super().__init__(
            f"the robot at {url}: {reason}; {outcome}",
            url=url,
            reason=reason,
            outcome=outcome,
            **({"stopped": True} if stopped_at is not None else {}),
            **evidence,
        )
        self.url = url
        self.reason = reason
        self.outcome = outcome
        self.stopped = stopped_at is not None
        self.stopped_at = stopped_at


class RobotLimitsError(ArmplanError):
    """The robot's own limits of a joint are narrower than the bridge's.

    The bridge checks every frame against its limits (the robot
    description's, a NAO H25 V5/V6): a robot that allows less (another
    model, a joint restricted in its settings) could be sent a frame it
    cannot follow.

    Attributes:
        url: The robot's NAOqi address.
        joint: NAO joint name, e.g. ``RShoulderRoll``.
        quantity: ``"lower"``, ``"upper"`` (position [rad]) or ``"velocity"``
            (speed [rad/s]).
        robot: The robot's value (``ALMotion.getLimits``).
        bridge: The bridge's value.
    """

    kind = "robot_limits"

    def __init__(
        self, url: str, joint: str, quantity: str, robot: float, bridge: float
    ) -> None:
        what = {"lower": "lower limit", "upper": "upper limit"}.get(
            quantity, "speed limit"
        )
        super().__init__(
            f"the robot at {url} gives {joint} the {what} {robot:.5f} "
            f"(ALMotion.getLimits), narrower than the bridge's {bridge:.5f}: "
            "nothing was sent (is it a NAO H25 V5/V6?)",
            url=url,
            joint=joint,
            quantity=quantity,
            robot=float(robot),
            bridge=float(bridge),
        )
        self.url = url
        self.joint = joint
        self.quantity = quantity
        self.robot = float(robot)
        self.bridge = float(bridge)


# Errors of demonstration files and motion-model files (shared/demos, services/fit).


class DemoFileError(ArmplanError):
    """A demonstration file (MCAP, C3D, CSV, marker map) cannot be used.

    Attributes:
        path: The file.
        reason: What is wrong with it, e.g. the missing markers.
    """

    kind = "demo_file_error"

    def __init__(self, path: str, reason: str, **evidence: Any) -> None:
        super().__init__(f"{path}: {reason}", path=path, reason=reason, **evidence)
        self.path = path
        self.reason = reason


class ModelFileError(ArmplanError):
    """A motion-model file is missing, truncated, malformed or of another version.

    Attributes:
        path: The file.
        reason: What is wrong with it.
    """

    kind = "model_file_error"

    def __init__(self, path: str, reason: str, **evidence: Any) -> None:
        super().__init__(f"{path}: {reason}", path=path, reason=reason, **evidence)
        self.path = path
        self.reason = reason
