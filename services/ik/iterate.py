"""Iterating eq. 14 to a posture: approach, converge, restart.

The solver first walks the wrist to the target in 5 mm steps of eq. 14 (so
the null-space motion follows the movement, as in the paper) along an arc
about the shoulder: the direction turns at a steady rate while the distance
changes linearly. NAO's wrist lives in a thin shell (0.114-0.162 m from the
shoulder) and a straight line between two points of it often cuts through
the unreachable inside. It then iterates at the target until the task error
and the projected gradient vanish, with a Barzilai-Borwein null-space gain.
If the start's basin cannot reach the target (joint limits), it restarts from
fixed, seeded postures and keeps the reaching solution of lowest H. If H's
pull keeps every start off the target, the task alone is solved (H = 0):
a posture on the target is worth more than a lower H beside it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from services.ik.gpm import gpm_step
from services.ik.kernel.chain import Chain, ChainState, chain_for
from services.ik.measures import Measure, NoMeasure
from services.ik.task import WristTask
from shared.robot.arm_model import ArmModel
from shared.robot.side import Side

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
    chain = chain_for(arm)
    q = _approach(chain, task, active, measure, [float(v) for v in start])
    q, iterations = converge(chain, task, active, measure, q)
    if task_met(task, chain.state(q)):
        return np.array(q), iterations
    best, best_key = q, _score(task, measure, chain.state(q))
    seeds = _seeds(chain, start, active)
    for seed in seeds:
        trial, spent = converge(chain, task, active, measure, seed)
        iterations += spent
        key = _score(task, measure, chain.state(trial))
        if key < best_key:
            best, best_key = trial, key
    if best_key[0] > 0.0:  # H pulled every start off the target: reach it anyway
        for seed in [[float(v) for v in start], *seeds]:
            near = _approach(chain, task, active, NoMeasure(), seed)
            trial, spent = converge(chain, task, active, NoMeasure(), near)
            iterations += spent
            if task_met(task, chain.state(trial)):
                return np.array(trial), iterations
    return np.array(best), iterations


def shoulder_arc(
    shoulder: Sequence[float], start: Sequence[float], end: Sequence[float], n: int
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
    centre, first, last = (np.asarray(v, dtype=float) for v in (shoulder, start, end))
    a, b = first - centre, last - centre
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
    points = centre + directions * (ra + s * (rb - ra))
    points[-1] = last
    return points


def _approach(
    chain: Chain,
    task: WristTask,
    active: tuple[int, ...],
    measure: Measure,
    q: list[float],
) -> list[float]:
    """Walk the wrist to the target along an arc about the shoulder, 5 mm a step."""
    st = chain.state(q)
    distance = task.position_error(st)
    steps = max(1, math.ceil(distance / APPROACH_STEP))
    for goal in shoulder_arc(st.p_shoulder, st.p_wrist, task.position, steps):
        q = _step(chain, task.at(goal), active, measure, q, st, ALPHA0)[0]
        st = chain.state(q)
    return q


def _step(
    chain: Chain,
    task: WristTask,
    active: Sequence[int],
    measure: Measure,
    q: list[float],
    st: ChainState,
    alpha: float,
) -> tuple[list[float], list[float], tuple[int, ...], float]:
    """One eq. 14 step: (new q, projected gradient, null joints, task error size)."""
    err, cols = task.residual(st)
    step = gpm_step(
        q, err, cols, measure.gradient(st), active, chain.lower, chain.upper,
        alpha, MAX_STEP, MAX_NULL_STEP,
    )  # fmt: skip
    dq = step.dq
    new = [q[k] + dq[k] for k in range(len(q))]
    return new, step.projected_gradient, step.null_joints, _largest(err)


def _largest(values: Sequence[float]) -> float:
    """Largest magnitude of ``values``, 0 if there are none."""
    out = 0.0
    for v in values:
        out = max(out, abs(v))
    return out


def converge(
    chain: Chain,
    task: WristTask,
    active: tuple[int, ...],
    measure: Measure,
    q: list[float],
) -> tuple[list[float], int]:
    """Iterate eq. 14 at the target until task error and null-space step vanish.

    Returns:
        (q [rad] 5 floats, iterations spent).
    """
    alpha = ALPHA0
    previous: list[float] | None = None
    joints: tuple[int, ...] = ()
    best, best_at = math.inf, 0
    for iteration in range(1, MAX_ITERATIONS + 1):
        q, projected, used, size = _step(
            chain, task, active, measure, q, chain.state(q), alpha
        )
        if size < 0.5 * best:
            best, best_at = size, iteration
        elif size > TOLERANCE and iteration - best_at > STALL:
            return q, iteration
        null_move = alpha * _largest(projected)
        if size < TASK_DONE and null_move < NULL_DONE:
            return q, iteration
        if previous is not None and used == joints:
            alpha = _barzilai_borwein(alpha, previous, projected)
        elif previous is not None:
            alpha = ALPHA0
        previous, joints = projected, used
    return q, MAX_ITERATIONS


def _barzilai_borwein(alpha: float, before: list[float], after: list[float]) -> float:
    """Next null-space gain from two successive projected gradients."""
    pp = cross = 0.0
    for k, b in enumerate(before):
        pp += b * b
        cross += b * after[k]
    curvature = pp - cross
    if pp <= 0.0 or curvature <= 0.0:
        return min(alpha * 2.0, ALPHA_MAX)
    return min(max(alpha * pp / curvature, ALPHA_MIN), ALPHA_MAX)


def task_met(task: WristTask, st: ChainState) -> bool:
    """True if the posture ``st`` meets the task within the accepted tolerances."""
    return (
        task.position_error(st) <= TOLERANCE and task.palm_error(st) <= ROLL_TOLERANCE
    )


def _score(task: WristTask, measure: Measure, st: ChainState) -> tuple[float, float]:
    """Sort key: task failure first (0 if met), then H."""
    miss = 0.0 if task_met(task, st) else task.position_error(st) + task.palm_error(st)
    return miss, measure.value(st)


def _seeds(
    chain: Chain, start: np.ndarray, active: tuple[int, ...]
) -> list[list[float]]:
    """Fixed restart postures: start, with the active joints drawn in their ranges.

    The draws are the same fractions of the ranges for both arms, read from
    the mirrored end for the left arm's mirrored joints (all but
    ShoulderPitch), so a left-arm solve restarts from the mirrors of the
    right arm's seeds and ends in the mirror of its answer (the same seeds
    for both arms once gave the left arm other postures and plans up to
    0.6 s shorter or longer).
    """
    rng = np.random.default_rng(SEED)
    idx = np.array(active)
    lower, upper = chain.limits.lower[idx], chain.limits.upper[idx]
    margin = 0.05 * (upper - lower)
    low, high = lower + margin, upper - margin
    mirrored = (chain.side is Side.LEFT) & (idx != 0)  # 0: ShoulderPitch
    seeds = []
    for _ in range(N_SEEDS):
        share = rng.random(len(idx))  # what rng.uniform(low, high) draws
        share = np.where(mirrored, 1.0 - share, share)
        q = np.array(start, dtype=float)
        q[idx] = low + (high - low) * share
        seeds.append([float(v) for v in q])
    return seeds
