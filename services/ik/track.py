"""Follow a wrist path point by point, each point moved by its own primitive.

This is the loop the motion decision, the IK service and the planner share:
``choose(k, kin)`` names the primitive for path point k from the arm's state
there (the motion decision, or a list of decisions already made), and one
step of eq. 14 on that primitive's active joints, with its measure, moves the
arm to the point. Run twice with the same choices it gives the same joint
path, bit for bit, which is what lets the decide and ik services split the
work.

A primitive's measure is built when its phase starts (when the chosen
primitive changes), from the posture there: H_G remembers where its elbow
started and how far the wrist was from the goal (eq. 20-21).

Where a primitive's joints cannot follow the path (a one-joint primitive off
its circle, the shoulder swing off its sphere) the wrist leaves the path; if
it strays more than ``PROMOTE_AFTER`` the point is moved by the full-arm
primitive of the same task instead, and the label says so. At the last point
the tracker converges to the goal exactly.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from services.ik.gpm import gpm_step
from services.ik.iterate import converge
from services.ik.measures import Measure, MeasureParams
from services.ik.measures import factory as measure_factory
from services.ik.task import WristTask, controls_radius
from shared.messages.method import Method
from shared.primitives import FULL_GRASP, FULL_REACH, Primitive
from shared.robot.arm_model import ArmModel, Kinematics

#: Chooses the primitive for path point k from the arm's state there.
Chooser = Callable[[int, Kinematics], Primitive]

#: Null-space gain while following a path [rad^2 per unit of H].
ALPHA = 1.0
#: Largest joint change per path point by the task / null-space part [rad].
MAX_STEP, MAX_NULL_STEP = 0.2, 0.02
#: Newton iterations per path point at most, and their stopping error [m].
ITERATIONS, CLOSE_ENOUGH = 3, 1e-5
#: Distance from the path beyond which a point is moved by the full-arm primitive [m].
PROMOTE_AFTER = 0.005
ALL_JOINTS = (0, 1, 2, 3, 4)
POSITION_JOINTS = {0, 1, 2, 3}


class TrackedPath(NamedTuple):
    """A joint path that follows a wrist path.

    Attributes:
        q: Joint angles [rad], shape (n, 5).
        wrist: Wrist positions reached [m], shape (n, 3).
        labels: What moved the arm at each point: a primitive's name, or the
            baseline method's name, shape (n,).
    """

    q: np.ndarray
    wrist: np.ndarray
    labels: list[str]


class _Phase(NamedTuple):
    label: str
    active: np.ndarray
    measure: Measure
    task: WristTask


def track_path(
    arm: ArmModel,
    positions: np.ndarray,
    start: np.ndarray,
    choose: Chooser | None,
    *,
    method: Method = Method.MP,
    palm: np.ndarray | None = None,
    params: MeasureParams | None = None,
) -> TrackedPath:
    """Joint angles that move the wrist along ``positions``.

    Args:
        arm: The arm.
        positions: Wrist path [m], shape (n, 3); the last point is the goal.
        start: Posture at the start [rad], shape (5,), within the limits.
        choose: The primitive for each point (method ``mp``); ignored by the
            baselines, which move all joints.
        method: ``mp``, ``least-norm`` or ``single``.
        palm: Palm direction to reach (unit, shape (3,)) for primitives that
            turn the wrist, or ``None``.
        params: Measure coefficients (defaults if ``None``).

    Returns:
        The tracked path; ``q`` stays within the joint limits.
    """
    params = params or MeasureParams()
    positions = np.asarray(positions, dtype=float)
    goal = positions[-1]
    q = np.array(start, dtype=float)
    out_q, out_wrist, labels = (
        np.empty((len(positions), 5)),
        np.empty((len(positions), 3)),
        [],
    )
    phase: _Phase | None = None
    for k, point in enumerate(positions):
        kin = arm.kinematics(q)
        wanted = _wanted(arm, method, choose, k, kin)
        if phase is None or phase.label != _label(method, wanted):
            phase = _start_phase(arm, method, wanted, kin, goal, palm, params)
        q, kin = _follow(arm, phase, point, q, kin)
        if wanted is not None and _strays(phase, kin, point, wanted):
            phase = _start_phase(
                arm, method, _full(wanted), arm.kinematics(q), goal, palm, params
            )
            q, kin = _follow(arm, phase, point, q, kin)
        if k == len(positions) - 1:
            q, _ = converge(
                arm,
                phase.task._replace(position=point),
                tuple(phase.active),
                phase.measure,
                q,
            )
            kin = arm.kinematics(q)
        out_q[k], out_wrist[k] = q, kin.wrist
        labels.append(phase.label)
    return TrackedPath(out_q, out_wrist, labels)


def _wanted(
    arm: ArmModel, method: Method, choose: Chooser | None, k: int, kin: Kinematics
) -> Primitive | None:
    if method is not Method.MP:
        return None
    if choose is None:
        raise ValueError("method mp needs a chooser of primitives")
    return choose(k, kin)


def _label(method: Method, primitive: Primitive | None) -> str:
    return method.value if primitive is None else primitive.name


def _start_phase(
    arm: ArmModel,
    method: Method,
    primitive: Primitive | None,
    kin: Kinematics,
    goal: np.ndarray,
    palm: np.ndarray | None,
    params: MeasureParams,
) -> _Phase:
    """Active joints, measure and task of a new phase, built at ``kin``."""
    if primitive is None:
        factory = measure_factory.for_baseline(method, params)
        task = WristTask(goal, palm, arm.side.sign)
        return _Phase(method.value, np.array(ALL_JOINTS), factory(kin), task)
    factory = measure_factory.for_primitive(primitive, goal, params)
    turn = palm if primitive.orients_wrist else None
    task = WristTask(
        goal, turn, arm.side.sign, radial=controls_radius(primitive.active)
    )
    return _Phase(primitive.name, np.array(primitive.active), factory(kin), task)


def _follow(
    arm: ArmModel, phase: _Phase, point: np.ndarray, q: np.ndarray, kin: Kinematics
) -> tuple[np.ndarray, Kinematics]:
    """Steps of eq. 14 towards ``point`` (at most ``ITERATIONS``)."""
    task = phase.task._replace(position=point)
    for _ in range(ITERATIONS):
        err, jac = task.residual(kin)
        step = gpm_step(
            q,
            err,
            jac,
            phase.measure.gradient(kin),
            phase.active,
            arm.limits,
            ALPHA,
            MAX_STEP,
            MAX_NULL_STEP,
        )
        q = q + step.dq
        kin = arm.kinematics(q)
        if float(np.max(np.abs(err))) < CLOSE_ENOUGH:
            break
    return q, kin


def _strays(
    phase: _Phase, kin: Kinematics, point: np.ndarray, wanted: Primitive
) -> bool:
    """True if a primitive that cannot reach every point left the path too far."""
    if set(wanted.active) >= POSITION_JOINTS:
        return False
    return float(np.linalg.norm(kin.wrist - point)) > PROMOTE_AFTER


def _full(primitive: Primitive) -> Primitive:
    """The full-arm primitive with the same wrist task."""
    return FULL_GRASP if primitive.orients_wrist else FULL_REACH
