"""Solve one posture: choose joints and measure by method and primitive, iterate.

Methods (``shared.messages.Method``):
    mp          The paper's method. With a primitive, only its active joints
                move and its IK method applies (closed form or GPM with its
                measure). Without one, the reaching primitive with every
                position joint (S_R E_PR W_P), or the grasping one with all
                five (S_R E_PR W_PR) when a palm direction is wanted.
    least-norm  All joints, damped pseudo-inverse, no null-space term.
    single      All joints, one measure (NTPE) for the whole movement.

The iterative solver lives in ``iterate.py``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from services.ik.elbow_turn import SWIVELS, turned_clear
from services.ik.geometric import (
    solve_elbow_triangle,
    solve_shoulder_rotation,
    solve_wrist_turn,
)
from services.ik.iterate import ROLL_TOLERANCE, TOLERANCE, solve_gpm
from services.ik.kernel.chain import ChainState, chain_for
from services.ik.measures import MeasureParams
from services.ik.measures import factory as measure_factory
from services.ik.measures.factory import MeasureFactory
from services.ik.palm_reached import palm_reached
from services.ik.reach_advice import reach_advice
from services.ik.reach_then_turn import turn_wrist
from services.ik.swivel_reach import check_swivel
from services.ik.task import WristTask
from shared.errors import (
    InvalidInputError,
    PrimitiveCannotReachError,
    UnreachableTargetError,
)
from shared.messages import IKRequest, IKResult, Method
from shared.primitives import FULL_GRASP, FULL_REACH, IKMethod, Primitive, get_primitive
from shared.robot.arm_model import ArmModel
from shared.robot.body import check_target_clear, collision_error, first_near
from shared.robot.postures import rest

ALL_JOINTS = (0, 1, 2, 3, 4)
ELBOW_YAW, ELBOW_ROLL = 2, 3
#: Joints that move the wrist's position (WristYaw only turns it).
POSITION_JOINTS = {0, 1, 2, 3}


class IKSolution(NamedTuple):
    """A solved posture.

    Attributes:
        q: Joint angles [rad], shape (5,).
        wrist: Wrist position reached [m], shape (3,).
        error: Wrist-to-target distance [m].
        primitive: The primitive whose joints moved, or ``None`` (baselines).
        method: The method used.
        iterations: Iterations spent (0 for closed-form solutions).
        swivel: Elbow swivel angle reached [rad] when a swivel goal was
            given (S_R E_P W_R), else ``None``.
    """

    q: np.ndarray
    wrist: np.ndarray
    error: float
    primitive: str | None
    method: Method
    iterations: int
    swivel: float | None = None


class Plan(NamedTuple):
    """How one request will be solved: active joints and measure."""

    primitive: Primitive | None
    active: tuple[int, ...]
    measure: MeasureFactory


def solve_request(arm: ArmModel, request: IKRequest) -> IKResult:
    """Solve an :class:`IKRequest` (validated already) and package the answer.

    With a palm direction, the answer also says the palm normal reached and
    its angle from the direction (``palm_reached``): the IK meets the palm's
    roll about the forearm, not the direction itself.
    """
    palm = None if request.palm is None else np.array(request.palm)
    start = rest(arm.side) if request.start is None else np.array(request.start)
    check_target(arm, np.array(request.target))
    solution = solve(
        arm,
        np.array(request.target),
        method=request.method,
        primitive=request.primitive,
        palm=palm,
        start=start,
        swivel=request.swivel,
        params=request.measures,
    )
    solution = _clear_of_body(arm, solution, palm, request.primitive is not None)
    return IKResult(
        arm=arm.side,
        joints=dict(zip(arm.joint_names, (float(v) for v in solution.q), strict=False)),
        wrist=tuple(float(v) for v in solution.wrist),
        target=request.target,
        error=solution.error,
        primitive=solution.primitive,
        method=solution.method,
        iterations=solution.iterations,
        swivel_goal=request.swivel,
        swivel_reached=solution.swivel,
        palm_reached=None
        if request.palm is None
        else palm_reached(arm, solution.q, request.palm),
    )


def _clear_of_body(
    arm: ArmModel, solution: IKSolution, palm: np.ndarray | None, named: bool
) -> IKSolution:
    """``solution``, its elbow turned if its posture comes near NAO's body.

    The target check keeps the hand's ball at the wrist clear; the rest of
    the arm can still come near (``services.ik.elbow_turn``). A primitive
    the caller named is not turned (its inactive joints would move).

    Raises:
        BodyCollisionError: no swivel tried takes it clear, or a named
            primitive's posture is near.
    """
    near = first_near(arm, solution.q[None, :])
    if near is None:
        return solution
    q = None if named else turned_clear(arm, solution.q, palm)
    if q is None:
        advice = (
            "a named primitive's posture is not turned: ask without it, or for "
            "another target"
            if named
            else f"turning its elbow about the wrist (up to {SWIVELS[-1]:g} rad "
            "either way) did not take it clear: ask for another target"
        )
        raise collision_error(
            arm, near, 0.0, what="the posture the IK found", at="", advice=advice
        )
    label = (FULL_GRASP if palm is not None else FULL_REACH).name
    return solution._replace(
        q=q,
        wrist=arm.fk(q).wrist,
        primitive=label if solution.method is Method.MP else solution.primitive,
    )


def solve(
    arm: ArmModel,
    target: np.ndarray,
    *,
    method: Method = Method.MP,
    primitive: str | None = None,
    palm: np.ndarray | None = None,
    start: np.ndarray | None = None,
    swivel: float | None = None,
    params: MeasureParams | None = None,
) -> IKSolution:
    """The posture that puts the wrist on ``target`` (see the module docstring).

    Args:
        arm: The arm.
        target: Wrist target in the torso frame [m], shape (3,).
        method: ``mp``, ``least-norm`` or ``single``.
        primitive: Name of the primitive to use (``mp`` only).
        palm: Wanted palm direction, unit, shape (3,), or ``None``.
        start: Start posture [rad], shape (5,); default: hanging at rest.
        swivel: Swivel goal for S_R E_P W_R [rad].
        params: Measure coefficients; defaults if ``None``.

    Raises:
        JointLimitError: if ``start`` is outside the joint ranges.
        UnreachableTargetError: if no posture within the limits reaches it;
            ``PalmRollOutOfRangeError`` (one of them): a posture reaches it,
            but the roll that faces ``palm`` there lies beyond WristYaw's
            range (``services.ik.reach_then_turn``; with the palm the
            solver had stopped short of the target).
        PrimitiveCannotReachError: if the primitive's joints cannot reach it.
        SwivelNotReachedError: if S_R E_P W_R holds the wrist but a joint
            limit stops the elbow short of ``swivel`` (``swivel_reach``).
        InvalidInputError: for a primitive with a baseline method, or a palm
            direction for a primitive that does not orient the wrist.
    """
    params = params or MeasureParams()
    start = rest(arm.side) if start is None else np.asarray(start, dtype=float)
    arm.limits.check(start, where="in the start posture")
    target = np.asarray(target, dtype=float)
    plan = _plan(arm, method, primitive, palm, swivel, target, params)
    check_reachable(arm, target)
    if plan.primitive is not None and plan.primitive.ik.geometric:
        return _closed_form(arm, plan.primitive, start, target, palm)
    task = WristTask.make(target, palm, arm.side.sign)
    if plan.primitive is not None and not plan.primitive.moves_wrist:
        _check_held(arm, plan.primitive, start, target)
    measure = plan.measure(chain_for(arm).state(start))
    q, iterations = solve_gpm(arm, task, plan.active, measure, start)
    try:
        solution = _accept(arm, plan, task, q, method, iterations)
    except UnreachableTargetError:
        if palm is None or plan.primitive not in (None, FULL_GRASP):
            raise
        solution = _reach_then_turn(arm, target, palm, method, start, params)
    if swivel is None:
        return solution
    return solution._replace(swivel=check_swivel(arm, plan.active, q, swivel))


def _reach_then_turn(
    arm: ArmModel,
    target: np.ndarray,
    palm: np.ndarray,
    method: Method,
    start: np.ndarray,
    params: MeasureParams,
) -> IKSolution:
    """The target reached without the palm, then WristYaw turned to face it.

    For when the solve with the palm stopped short of the target
    (``services.ik.reach_then_turn``): the answer is a posture that does
    both, or the error that the palm cannot be faced there.

    Raises:
        UnreachableTargetError: no posture reaches the target either.
        PalmRollOutOfRangeError: it is reached, but WristYaw cannot face the palm.
    """
    reached = solve(arm, target, method=method, start=start, params=params)
    q = turn_wrist(arm, reached.q, target, palm)
    label = FULL_GRASP.name if method is Method.MP else None
    return reached._replace(q=q, wrist=arm.fk(q).wrist, primitive=label)


def check_reachable(arm: ArmModel, target: np.ndarray) -> None:
    """Raise UnreachableTargetError if the wrist never gets this near or far."""
    shoulder = arm.fk(rest(arm.side)).shoulder
    distance = math.dist(target, shoulder)  # no overflow warning for 1e308
    low, high = arm.reach
    if not low - TOLERANCE <= distance <= high + TOLERANCE:
        raise UnreachableTargetError(
            target,
            arm=arm.side.value,
            distance=distance,
            reach=arm.reach,
            advice=reach_advice(arm, target),
        )


def check_target(arm: ArmModel, target: np.ndarray) -> None:
    """Raise if a target asked for is out of reach, or in NAO's body.

    What a request's target must pass (the ik service, the planner, the
    command line), beyond :func:`check_reachable`: the wrist there must
    keep the hand clear of the torso, pelvis and head
    (``shared.robot.body``). :func:`solve` itself does not check the body:
    it is the solver, asked by the tracker for any point too.

    Raises:
        UnreachableTargetError: out of the reach shell; or
            ``TargetInBodyError`` (one of them), in the body.
    """
    check_reachable(arm, target)
    check_target_clear(arm, target)


def _plan(
    arm: ArmModel,
    method: Method,
    name: str | None,
    palm: np.ndarray | None,
    swivel: float | None,
    target: np.ndarray,
    params: MeasureParams,
) -> Plan:
    if method is not Method.MP:
        if name is not None:
            raise InvalidInputError(
                f"primitive applies to method 'mp' only, not {method.value!r}",
                field="primitive",
            )
        _check_swivel_used(swivel, f"method {method.value!r}")
        return Plan(None, ALL_JOINTS, measure_factory.for_baseline(method, params))
    primitive = (
        (FULL_GRASP if palm is not None else FULL_REACH)
        if name is None
        else get_primitive(name)
    )
    if primitive.ik is not IKMethod.GPM_NULL:
        _check_swivel_used(swivel, f"primitive {primitive.name!r}")
    if palm is not None and not primitive.orients_wrist:
        raise InvalidInputError(
            f"primitive {primitive.name!r} does not turn the wrist; a palm direction "
            "needs one with W_R or W_PR",
            field="palm",
        )
    return Plan(
        primitive,
        primitive.active,
        measure_factory.for_primitive(primitive, target, params, swivel),
    )


def _check_swivel_used(swivel: float | None, what: str) -> None:
    """Refuse a swivel goal that ``what`` would ignore."""
    if swivel is not None:
        raise InvalidInputError(
            f"swivel is the goal of the function primitive S_R E_P W_R; {what} "
            "does not use it (give primitive 'S_R E_P W_R')",
            field="swivel",
        )


def _closed_form(
    arm: ArmModel,
    primitive: Primitive,
    start: np.ndarray,
    target: np.ndarray,
    palm: np.ndarray | None,
) -> IKSolution:
    if primitive.ik is IKMethod.ELBOW_TRIANGLE:
        sol = solve_elbow_triangle(arm, start, target, TOLERANCE)
    elif primitive.ik is IKMethod.SHOULDER_ROTATION:
        sol = solve_shoulder_rotation(arm, start, target, TOLERANCE)
    else:
        sol = solve_wrist_turn(arm, start, target, palm, TOLERANCE)
    return IKSolution(sol.q, sol.wrist, sol.residual, primitive.name, Method.MP, 0)


def _check_held(
    arm: ArmModel, primitive: Primitive, start: np.ndarray, target: np.ndarray
) -> None:
    wrist = arm.fk(start).wrist
    residual = float(np.linalg.norm(wrist - target))
    if residual > TOLERANCE:
        raise PrimitiveCannotReachError(
            primitive.name,
            target,
            wrist,
            residual,
            "a function primitive holds the wrist in place",
        )


def _why(arm: ArmModel, plan: Plan, task: WristTask, st: ChainState) -> str:
    """Why a primitive's active joints miss the target.

    With ElbowRoll still, only ElbowYaw changes the wrist's distance from the
    shoulder (NAO's elbow offset), within ``ArmModel.distance_span_at``: a
    target beyond that span is named as the reason.
    """
    assert plan.primitive is not None
    joints = ", ".join(plan.primitive.active_joints)
    if ELBOW_ROLL in plan.active or ELBOW_YAW not in plan.active:
        return f"only {joints} move"
    roll = st.qf[ELBOW_ROLL]
    low, high = arm.distance_span_at(roll)
    wanted = math.dist(task.position, st.p_shoulder)
    if low - TOLERANCE <= wanted <= high + TOLERANCE:
        return f"only {joints} move"
    return (
        f"only {joints} move, so with ElbowRoll at {roll:.4f} rad the wrist stays "
        f"{low:.4f}..{high:.4f} m from the shoulder (the target is {wanted:.4f} m "
        "from it)"
    )


def _accept(
    arm: ArmModel,
    plan: Plan,
    task: WristTask,
    q: np.ndarray,
    method: Method,
    iterations: int,
) -> IKSolution:
    """Package ``q``, or raise the error that explains why it misses."""
    arm.limits.check(q, where="in the solution")
    st = chain_for(arm).state(q)
    error = task.position_error(st)
    name = None if plan.primitive is None else plan.primitive.name
    if error > TOLERANCE:
        if plan.primitive is not None and not set(plan.active) >= POSITION_JOINTS:
            raise PrimitiveCannotReachError(
                plan.primitive.name,
                task.position,
                st.wrist,
                error,
                _why(arm, plan, task, st),
            )
        distance = math.dist(task.position, st.p_shoulder)
        raise UnreachableTargetError(
            task.position,
            arm=arm.side.value,
            distance=distance,
            reach=arm.reach,
            residual=error,
            palm=task.palm,
        )
    if task.palm_error(st) > ROLL_TOLERANCE:
        raise PrimitiveCannotReachError(
            name or method.value,
            task.position,
            st.wrist,
            error,
            f"the palm's roll about the forearm stays "
            f"{math.degrees(task.palm_error(st)):.1f} deg short of turning it "
            "towards the wanted direction",
        )
    return IKSolution(q, st.wrist, error, name, method, iterations)
