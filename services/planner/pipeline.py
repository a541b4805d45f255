"""Task in, trajectory out: wrist path, motion decision, IK, timing.

For each target of a task the planner draws a human-like wrist path from
where the arm is (:mod:`services.planner.reach_path`), asks the decide stage
for the primitive of every point (method ``mp``), the ik stage for the joint
path, and then the timing stage for one trajectory through all movements,
each at human pace (Table 4's law, scaled to NAO) or as fast as a smooth
profile along the path allows (``--fastest``, not time-optimal), resting
``dwell`` seconds at each target. The stages are injected
(:class:`~services.planner.stages.Stages`): here, or the services over Zenoh.
Where a target asks for a palm direction, the trajectory says the palm
reached there (``Trajectory.palm_reached``): the IK turns the palm's roll
about the forearm, so the palm can end tens of degrees off the direction.

With a timed wrist path instead of targets, the joint angles come at exactly
its times: no retiming, but every limit checked. The trajectory starts on
the path: if the start posture's wrist is more than ``ON_PATH`` from the
path's first sample, the first posture is the IK solution there (the
request's method, seeded with the start posture), so a path need not begin
exactly where the arm hangs (a retargeted demonstration starts 1-3 cm from
NAO's rest wrist). The robot bridge moves the arm slowly to that posture
before it plays the trajectory. A timed path is a contract: if the wrist of
any sample's posture is more than the request's ``path_tolerance`` (default
``PATH_TOLERANCE``) from the path's sample, the plan is refused
(``OffPathError``, naming the sample, its time and the distance), where
the tracker would otherwise have left the path (its joint-space detour to
the end posture, or its drift of up to ``DETOUR_AFTER``). A path not
sampled evenly every 10 ms is tracked on that grid and read back at its
own times (:mod:`services.planner.even_path`), so the joint path depends
on the wrist path, not on where it was sampled.
"""

from __future__ import annotations

import bisect
import logging
from typing import NamedTuple

import numpy as np

from services.ik import check_target, solve
from services.planner.build import trajectory_message, with_palms_reached
from services.planner.clear_of import kept_clear_of
from services.planner.clear_swivel import REFUSED_TRIED, keep_clear
from services.planner.decision_times import on_path_clock, timed_decisions
from services.planner.even_path import at_path_times, even_grid, tracked_as_given
from services.planner.given_clear import timed_clear
from services.planner.grid_reach import check_grid_within_reach
from services.planner.path_reach import (
    STAGE_SLACK,
    check_path_clear,
    check_path_within_reach,
)
from services.planner.reach_path import reach_wrist_path
from services.planner.stages import LocalStages, Stages
from services.timing import reach_duration
from services.timing.request_limits import request_limits
from services.timing.sample_cap import FEWER_SAMPLES, check_payload, check_samples
from shared.errors import (
    LimitViolationError,
    ModelChangedError,
    OffPathError,
    UnreachableTargetError,
)
from shared.messages import (
    DecideRequest,
    Decision,
    JointPath,
    Method,
    PathIKRequest,
    PlanRequest,
    TimingRequest,
    TimingSegment,
    Trajectory,
    WristPath,
)
from shared.messages.measure_params import MeasureParams
from shared.robot import load_arm
from shared.robot.arm_model import ArmModel
from shared.robot.body import (
    BodyPart,
    check_postures_clear,
    check_start_clear,
    check_target_clear,
    first_near,
)
from shared.robot.postures import rest

log = logging.getLogger("armplan.planner")

#: A start posture whose wrist is this close to a wrist path's first sample is
#: on the path [m]; farther, the trajectory starts at the IK solution there.
#: (It was 1 mm: a start 0.1-1 mm off was kept and the tracker closed the gap
#: in its first step, a jump the limits refused, jerk 957 > 661 rad/s^3.)
ON_PATH = 1e-6
#: Farthest a sample's wrist may be from a timed wrist path's sample [m],
#: unless the request sets its own ``path_tolerance``. Paths the tracker
#: follows leave far less (measured on 40 reaches at 100 Hz, each method:
#: at most 0.18 mm on the planner's reach paths, 0.02 mm on the wrist of
#: slow joint motions); paths it cannot follow leave centimetres.
PATH_TOLERANCE = 1e-3
#: What to do about a wrist path given with times that breaks a limit.
GIVEN_PATH_ADVICE = (
    "the wrist path is played at its own times: slow it down, smooth its "
    "samples (noise as small as rounding to 1 um every 10 ms can pass the "
    "jerk limit), give fewer samples, or raise limits.jerk / limits.acceleration"
)


class PlanResult(NamedTuple):
    """A plan and what it was made of.

    Attributes:
        trajectory: The timed trajectory (the SPEC's trajectory JSON).
        wrist_paths: Each movement's planned wrist path.
        decisions: Each movement's decision (method ``mp``; else empty),
            with when the trajectory passes each of its points
            (``Decision.trajectory_times``).
        joint_paths: Each movement's joint path, before timing.
    """

    trajectory: Trajectory
    wrist_paths: list[WristPath]
    decisions: list[Decision]
    joint_paths: list[JointPath]


def plan(request: PlanRequest, stages: Stages | None = None) -> PlanResult:
    """The trajectory for a task (targets, or a timed wrist path).

    All its decisions come from one motion model (``Decision.model``): the
    decide stage is asked once per reach, and a plan during which the model
    was swapped (a fit landing) is made once more.

    Raises:
        ModelChangedError: the second plan's decisions also came from more
            than one model.
        UnreachableTargetError: a target (or a wrist-path sample) beyond reach;
            ``TargetInBodyError``: a target in NAO's body.
        BodyCollisionError: a posture of the trajectory brings the arm into
            NAO's body, or nearer it than ``shared.robot.body.MARGIN``.
        JointLimitError: a start posture outside the joint ranges.
        LimitViolationError: a wrist path timed faster than the limits allow.
        OffPathError: a wrist path the arm cannot follow within the tolerance.
        InvalidInputError: timing limits above the bridge's safety net.
        PrimitiveCannotReachError, InvalidInputError: from the stages.
    """
    stages = stages or LocalStages()
    result = _plan(request, stages)
    if len(_models(result)) > 1:
        log.info(
            "the motion model changed while planning (models %s): planning once more",
            ", ".join(_models(result)),
        )
        result = _plan(request, stages)
        if len(_models(result)) > 1:
            raise ModelChangedError([d.model for d in result.decisions])
    return result


def _models(result: PlanResult) -> list[str]:
    """The digests of the models a plan's decisions came from (known ones)."""
    return list(dict.fromkeys(d.model for d in result.decisions if d.model))


def _plan(request: PlanRequest, stages: Stages) -> PlanResult:
    """``plan``, its decisions' models not checked."""
    arm = load_arm(request.arm)
    start = rest(arm.side) if request.start is None else np.array(request.start)
    arm.limits.check(start, where="in the start posture")
    parts = kept_clear_of(arm, request)
    check_start_clear(arm, start, parts=parts)
    request_limits(arm.limits, request.limits)  # refused before any planning
    if request.wrist_path is not None:
        return _follow_given(arm, request, request.wrist_path, start, stages, parts)
    for target in request.targets:
        check_target(arm, np.array(target.position))
        if request.other_arm is not None:  # check_target kept it clear of the body
            check_target_clear(arm, target.position, parts=parts)
    timed = _movements(arm, request, stages, start, None)
    if first_near(arm, timed.trajectory.positions, parts=parts) is not None:
        timed = _movements(arm, request, stages, start, parts)  # go round
        _check_plan_clear(arm, timed.trajectory, parts, timed.tried)
    trajectory, decisions = timed.trajectory, timed.decisions
    paths, joints = timed.paths, timed.joints
    trajectory, decisions = timed_decisions(trajectory, decisions)
    trajectory = with_palms_reached(
        arm,
        trajectory,
        [target.palm for target in request.targets],
        [path.positions[-1] for path in joints],  # the trajectory stops there
    )
    check_payload(trajectory)
    return PlanResult(trajectory, paths, decisions, joints)


class _Timed(NamedTuple):
    """A task's movements and their trajectory, before its checks."""

    trajectory: Trajectory
    paths: list[WristPath]
    joints: list[JointPath]
    decisions: list[Decision]
    tried: list[bool]  # per movement: whether its elbow's turn was tried


def _movements(
    arm: ArmModel,
    request: PlanRequest,
    stages: Stages,
    start: np.ndarray,
    turn: tuple[BodyPart, ...] | None,
) -> _Timed:
    """Each target's movement from where the one before ended, timed as one.

    ``turn``: what a movement's elbow is turned to keep clear of
    (``clear_swivel.keep_clear``), or None to leave the movements as
    tracked. The planner tracks without turning first, and turns only when
    that trajectory comes near: the check costs about as much as the
    wrist path (``armplan bench``).
    """
    paths, joints, segments = [], [], []
    decisions: list[Decision] = []
    tried: list[bool] = []
    q = start
    for target in request.targets:
        path = reach_wrist_path(arm, q, target)
        joint_path = _movement(stages, request, path, q, decisions)
        near = False
        if turn is not None:
            joint_path, near = keep_clear(
                arm, joint_path, target.palm, request.method, turn
            )
        tried.append(near)
        paths.append(path)
        joints.append(joint_path)
        end = np.array(joint_path.positions[-1])
        pace = None if request.fastest else reach_duration(arm, q, end)
        segments.append(
            TimingSegment(
                joint_path=joint_path,
                duration=pace,
                dwell=target.dwell,
                hand=target.hand,
            )
        )
        q = end
    trajectory = stages.timing(
        TimingRequest(
            segments=segments,
            rate=request.rate,
            method=request.method,
            limits=request.limits,
        )
    )
    check_samples(len(trajectory.times), request.rate)
    return _Timed(trajectory, paths, joints, decisions, tried)


def _check_plan_clear(
    arm: ArmModel,
    trajectory: Trajectory,
    parts: tuple[BodyPart, ...],
    tried: list[bool],
) -> None:
    """``check_postures_clear`` on the plan, its advice the near movement's.

    Where the first posture too near belongs to a movement whose elbow was
    turned in vain (``tried``, one per movement), the refusal says so.
    """
    near = first_near(arm, trajectory.positions, parts=parts)
    if near is None:
        return
    times = trajectory.times
    at = times[near.sample] - times[0]
    starts = [segment[0] for segment in trajectory.point_times or [] if segment]
    movement = max(0, bisect.bisect_right(starts, at) - 1)
    turned = tried[movement] if len(starts) == len(tried) else any(tried)
    check_postures_clear(
        arm,
        trajectory.positions,
        times,
        parts=parts,
        advice=REFUSED_TRIED if turned else "",
    )


def track_movement(
    stages: Stages,
    path: WristPath,
    start: np.ndarray,
    method: Method,
    measures: MeasureParams | None,
) -> tuple[JointPath, Decision | None]:
    """Decide (method mp) and track one movement's wrist path from ``start``.

    ``measures`` None: the decision's (the motion model's weights), or for a
    baseline the shipped ones.

    Returns:
        The joint path, and the decision (None for a baseline).
    """
    begin = tuple(float(v) for v in start)
    decision = None
    if method is Method.MP:
        decision = stages.decide(
            DecideRequest(path=path, start=begin, measures=measures)
        )
    joint_path = stages.ik(
        PathIKRequest(
            path=path,
            start=begin,
            method=method,
            decision=decision,
            measures=measures,
        )
    )
    return joint_path, decision


def _movement(
    stages: Stages,
    request: PlanRequest,
    path: WristPath,
    start: np.ndarray,
    decisions: list[Decision],
) -> JointPath:
    """``track_movement`` for ``request``, its decision kept in ``decisions``."""
    joint_path, decision = track_movement(
        stages, path, start, request.method, request.measures
    )
    if decision is not None:
        decisions.append(decision)
    return joint_path


def _follow_given(
    arm: ArmModel,
    request: PlanRequest,
    path: WristPath,
    start: np.ndarray,
    stages: Stages,
    parts: tuple[BodyPart, ...],
) -> PlanResult:
    """Joint angles at the wrist path's own times (no retiming), limits checked.

    ``parts``: what the arm keeps clear of (``clear_of.kept_clear_of``).
    """
    check_path_within_reach(arm, path)
    check_path_clear(arm, path, parts)
    start = start_on_path(arm, path, start, request.method)
    check_start_clear(
        arm,
        start,
        "the posture that puts the wrist on the path's first sample",
        "start the path farther from the body, or give a start posture on it",
        parts,
    )
    decisions: list[Decision] = []
    grid = None if tracked_as_given(path.times) else even_grid(path)
    tracked = None
    try:
        if grid is None:
            joint_path = _movement(stages, request, path, start, decisions)
        else:  # tracked on an even grid: the joints do not depend on the sampling
            tracked = _track_grid(arm, stages, request, path, grid, start, decisions)
            joint_path = at_path_times(arm, path, tracked)
        limits = request_limits(arm.limits, request.limits)
        joint_path, timed, advice = timed_clear(
            arm, path, joint_path, request.method, limits, parts
        )
        check_on_path(arm, path, timed.positions, request.path_tolerance)
        check_postures_clear(
            arm, timed.positions, path.times, parts=parts, advice=advice
        )
    except LimitViolationError as error:
        raise error.advised(GIVEN_PATH_ADVICE) from None
    except OffPathError:
        if grid is not None:  # the curve drawn through the samples may be why
            tolerance = request.path_tolerance
            check_grid_within_reach(
                arm,
                path,
                grid,
                PATH_TOLERANCE if tolerance is None else tolerance,
                None if tracked is None else np.asarray(tracked.positions),
            )
        raise
    trajectory = trajectory_message(arm, [joint_path], timed, request.method)
    trajectory = with_palms_reached(arm, trajectory, [path.palm], [timed.positions[-1]])
    check_payload(trajectory, advice=FEWER_SAMPLES)
    decisions = on_path_clock(decisions, path.times[0])
    return PlanResult(trajectory, [path], decisions, [joint_path])


def _track_grid(
    arm: ArmModel,
    stages: Stages,
    request: PlanRequest,
    path: WristPath,
    grid: WristPath,
    start: np.ndarray,
    decisions: list[Decision],
) -> JointPath:
    """``_movement`` along ``grid``, the even grid through ``path``'s samples.

    Raises:
        UnreachableTargetError: the grid leaves the reach by more than the
            stages allow (``STAGE_SLACK``): named as the gap between two of
            ``path``'s samples, to fill with samples, not as a point of a
            grid the caller never gave.
    """
    try:
        return _movement(stages, request, grid, start, decisions)
    except UnreachableTargetError:
        check_grid_within_reach(arm, path, grid, STAGE_SLACK)
        raise


def start_on_path(
    arm: ArmModel, path: WristPath, start: np.ndarray, method: Method
) -> np.ndarray:
    """The posture [rad], (5,), whose wrist is on the path's first sample.

    ``start`` itself when its wrist is within ``ON_PATH`` of it; else the IK
    solution for that sample with ``method`` (primitive chosen by the
    method), seeded with ``start``, with the path's palm direction if any.
    """
    first = np.array(path.positions[0])
    if np.linalg.norm(arm.fk(start).wrist - first) <= ON_PATH:
        return start
    palm = None if path.palm is None else np.array(path.palm)
    return solve(arm, first, method=method, palm=palm, start=start).q


def check_on_path(
    arm: ArmModel, path: WristPath, q: np.ndarray, tolerance: float | None
) -> None:
    """Raise if a posture's wrist is farther than ``tolerance`` from its sample.

    Args:
        arm: The arm.
        path: The timed wrist path.
        q: Joint angles [rad], shape (n, 5), one row per path sample.
        tolerance: Farthest allowed [m]; None: ``PATH_TOLERANCE``.

    Raises:
        OffPathError: naming the sample farthest off, its time and distance.
    """
    limit = PATH_TOLERANCE if tolerance is None else tolerance
    wrists = np.array([arm.fk(posture).wrist for posture in q])
    errors = np.linalg.norm(wrists - np.array(path.positions), axis=1)
    k = int(np.argmax(errors))
    if errors[k] > limit:
        raise OffPathError(
            arm=arm.side.value,
            index=k,
            time=path.times[k],
            deviation=float(errors[k]),
            tolerance=limit,
            reason="the IK tracker, from the start posture and within the joint "
            "limits, did not stay on it",
        )
