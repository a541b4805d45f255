"""Iterating eq. 14 to a posture: approach, converge, restart.

The solver first walks the wrist to the target in 5 mm steps of eq. 14 (so
the null-space motion follows the movement, as in the paper) along an arc
about the shoulder: the direction turns at a steady rate while the distance
changes linearly. NAO's wrist lives in a thin shell (0.114-0.162 m from the
shoulder) and a straight line between two points of it often cuts through
the unreachable inside. It then iterates at the target until the task error
and the projected gradient vanish, with a Barzilai-Borwein null-space gain.
If the start's basin cannot reach the target (joint limits), it restarts from
fixed, seeded postures and keeps the reaching solution of lowest H.
"""

from __future__ import annotations

import math

import numpy as np

from services.ik.gpm import gpm_step
from services.ik.measures import Measure
from services.ik.task import WristTask
from shared.robot.arm_model import ArmModel

#: Largest accepted wrist error of a solution [m] (the contract says 1 mm).
TOLERANCE = 1e-4
#: Largest accepted palm roll error [rad].
ROLL_TOLERANCE = math.radians(1.0)
#: Wrist step of the approach phase [m].
APPROACH_STEP = 0.005
#: Largest joint change per iteration, by the task and by the null space [rad].
MAX_STEP, MAX_NULL_STEP = 0.2, 0.05
#: Iterations of the convergence phase.
MAX_ITERATIONS = 300
#: Convergence: task error [m or rad] and null-space step [rad].
TASK_DONE, NULL_DONE = 1e-7, 1e-8
#: Initial null-space gain and its bounds [rad^2 per unit of H].
ALPHA0, ALPHA_MIN, ALPHA_MAX = 1.0, 1e-2, 1e2
#: Give up on a start when the task error has not halved in this many iterations.
STALL = 25
#: Restart postures tried when the start's basin fails.
N_SEEDS = 24
SEED = 20231122


def solve_gpm(
    arm: ArmModel,
    task: WristTask,
    active: tuple[int, ...],
    measure: Measure,
    start: np.ndarray,
) -> tuple[np.ndarray, int]:
    """Posture meeting ``task`` with only ``active`` joints moving, minimising H.

    Approaches along an arc about the shoulder, converges at the target, and
    restarts from seeded postures if the start's basin misses the target.

    Args:
        arm: The arm.
        task: The wrist task.
        active: Indices of the joints allowed to move.
        measure: The performance measure H.
        start: Start posture [rad], shape (5,); the other joints keep it.

    Returns:
        (q [rad] shape (5,), iterations). ``q`` may miss the task if no
        posture reaches it; the caller checks.
    """
    q = _approach(arm, task, active, measure, start)
    q, iterations = converge(arm, task, active, measure, q)
    if task_met(arm, task, q):
        return q, iterations
    best, best_key = q, _score(arm, task, measure, q)
    for seed in _seeds(arm, start, active):
        trial, spent = converge(arm, task, active, measure, seed)
        iterations += spent
        key = _score(arm, task, measure, trial)
        if key < best_key:
            best, best_key = trial, key
    return best, iterations


def shoulder_arc(
    shoulder: np.ndarray, start: np.ndarray, end: np.ndarray, n: int
) -> np.ndarray:
    """``n`` points from ``start`` (excluded) to ``end`` on an arc about the shoulder.

    The direction from the shoulder turns at a steady rate (slerp) while the
    distance changes linearly.

    Args:
        shoulder: Centre of the arc [m], shape (3,).
        start: First position [m], shape (3,), not included.
        end: Last position [m], shape (3,).
        n: Number of points.

    Returns:
        Positions [m], shape (n, 3); the last one is ``end``.
    """
    a, b = start - shoulder, end - shoulder
    ra, rb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    ua, ub = a / ra, b / rb
    angle = math.acos(min(max(float(ua @ ub), -1.0), 1.0))
    s = np.arange(1, n + 1)[:, None] / n
    if angle < 1e-6:
        directions = ua + s * (ub - ua)
    else:
        directions = (np.sin((1 - s) * angle) * ua + np.sin(s * angle) * ub) / math.sin(
            angle
        )
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return shoulder + directions * (ra + s * (rb - ra))


def _approach(
    arm: ArmModel,
    task: WristTask,
    active: tuple[int, ...],
    measure: Measure,
    q: np.ndarray,
) -> np.ndarray:
    """Walk the wrist to the target along an arc about the shoulder, 5 mm a step."""
    points = arm.fk(q)
    steps = max(
        1,
        math.ceil(float(np.linalg.norm(task.position - points.wrist)) / APPROACH_STEP),
    )
    active_idx = np.array(active)
    for goal in shoulder_arc(points.shoulder, points.wrist, task.position, steps):
        kin = arm.kinematics(q)
        err, jac = task._replace(position=goal).residual(kin)
        step = gpm_step(
            q,
            err,
            jac,
            measure.gradient(kin),
            active_idx,
            arm.limits,
            ALPHA0,
            MAX_STEP,
            MAX_NULL_STEP,
        )
        q = q + step.dq
    return q


def converge(
    arm: ArmModel,
    task: WristTask,
    active: tuple[int, ...],
    measure: Measure,
    q: np.ndarray,
) -> tuple[np.ndarray, int]:
    """Iterate eq. 14 at the target until task error and null-space step vanish."""
    active_idx, alpha = np.array(active), ALPHA0
    previous: np.ndarray | None = None
    joints: tuple[int, ...] = ()
    best, best_at = math.inf, 0
    for iteration in range(1, MAX_ITERATIONS + 1):
        kin = arm.kinematics(q)
        err, jac = task.residual(kin)
        size = float(np.max(np.abs(err)))
        if size < 0.5 * best:
            best, best_at = size, iteration
        elif size > TOLERANCE and iteration - best_at > STALL:
            return q, iteration
        step = gpm_step(
            q,
            err,
            jac,
            measure.gradient(kin),
            active_idx,
            arm.limits,
            alpha,
            MAX_STEP,
            MAX_NULL_STEP,
        )
        q = q + step.dq
        null_move = alpha * float(np.max(np.abs(step.projected_gradient), initial=0.0))
        if size < TASK_DONE and null_move < NULL_DONE:
            return q, iteration
        if previous is not None and step.null_joints == joints:
            alpha = _barzilai_borwein(alpha, previous, step.projected_gradient)
        elif previous is not None:
            alpha = ALPHA0
        previous, joints = step.projected_gradient, step.null_joints
    return q, MAX_ITERATIONS


def _barzilai_borwein(alpha: float, before: np.ndarray, after: np.ndarray) -> float:
    """Next null-space gain from two successive projected gradients."""
    pp = float(before @ before)
    curvature = pp - float(before @ after)
    if pp <= 0.0 or curvature <= 0.0:
        return min(alpha * 2.0, ALPHA_MAX)
    return min(max(alpha * pp / curvature, ALPHA_MIN), ALPHA_MAX)


def task_met(arm: ArmModel, task: WristTask, q: np.ndarray) -> bool:
    """True if ``q`` meets the task within the accepted tolerances."""
    kin = arm.kinematics(q)
    return (
        task.position_error(kin) <= TOLERANCE and task.palm_error(kin) <= ROLL_TOLERANCE
    )


def _score(
    arm: ArmModel, task: WristTask, measure: Measure, q: np.ndarray
) -> tuple[float, float]:
    """Sort key: task failure first (0 if met), then H."""
    kin = arm.kinematics(q)
    miss = (
        0.0
        if task_met(arm, task, q)
        else task.position_error(kin) + task.palm_error(kin)
    )
    return miss, measure.value(kin)


def _seeds(
    arm: ArmModel, start: np.ndarray, active: tuple[int, ...]
) -> list[np.ndarray]:
    """Fixed restart postures: start, with the active joints drawn in their ranges."""
    rng = np.random.default_rng(SEED)
    idx = np.array(active)
    low = arm.limits.lower[idx] + 0.05 * arm.limits.span[idx]
    high = arm.limits.upper[idx] - 0.05 * arm.limits.span[idx]
    seeds = []
    for _ in range(N_SEEDS):
        q = start.copy()
        q[idx] = rng.uniform(low, high)
        seeds.append(q)
    return seeds
