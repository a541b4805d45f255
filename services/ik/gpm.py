"""The gradient projection method (paper eq. 14) on a primitive's active joints.

    dq = J+ dx - alpha (I - J+ J) grad H

(the paper writes +k with k < 0 to descend H). J is given by columns, one per
joint. One factorisation of J J^T serves both parts. It is undamped where J
is well conditioned: near an optimum the projected gradient is tiny while the
raw gradient is not, and damping would leak lambda^2 / sigma^2 of the raw
gradient into the task, as large as what is left to descend (that stalled
convergence). Near a singularity (a stretched arm) the damped J+ keeps steps
bounded.

Joint limits are kept by each priority in turn, so no step ever leaves them:
    1. The task step J+ dx uses joint clamping: a joint it would push out of
       range stops at the limit and the others solve the remaining error.
    2. The null-space step is shortened so that no joint crosses a limit; a
       joint already on a limit that the null-space motion would push further
       is dropped from that motion, which is projected again without it.
       With ``margin`` > 0 a joint moving towards a limit closer than
       ``margin`` also scales the step down by smoothstep(distance / margin),
       so it slows down smoothly (no kink in its velocity) and never quite
       reaches the limit: the path tracker uses this, as its joint path must
       stay smooth; the posture solver uses margin = 0, where only the end
       matters. When H's optimum lies beyond a limit this leaves the posture
       on (or at) the limit: the optimum within the range.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final, NamedTuple

from services.ik.kernel.small import NormalSolver, NormalSolver3, normal_solver

#: Damping near singularities [m^2]: lambda^2 with lambda = 1e-4 m.
SINGULAR_DAMPING: Final = 1e-8
#: A null-space step shorter than this fraction counts as blocked by a limit.
BLOCKED: Final = 1e-6

Columns = Sequence[Sequence[float]]


class Step(NamedTuple):
    """Result of one GPM step.

    Attributes:
        dq: Joint change [rad], 5 floats, zero outside the active joints.
        projected_gradient: The gradient of H projected on the null space of
            the joints the null-space motion used, zero elsewhere (5 floats):
            zero at an optimum within the limits.
        null_joints: Indices of the joints the null-space motion used.
    """

    dq: list[float]
    projected_gradient: list[float]
    null_joints: tuple[int, ...]


def solver(cols: Columns, free: Sequence[int]) -> NormalSolver | NormalSolver3:
    """The (undamped unless near-singular) pseudo-inverse of J's free columns."""
    return normal_solver(cols, free, 0.0, SINGULAR_DAMPING)


def _capped(step: list[float], largest: float) -> list[float]:
    biggest = max(map(abs, step)) if step else 0.0
    if biggest <= largest:
        return step
    scale = largest / biggest
    return [v * scale for v in step]


def task_step(
    q: Sequence[float],
    error: Sequence[float],
    cols: Columns,
    active: Sequence[int],
    lower: Sequence[float],
    upper: Sequence[float],
    max_step: float,
    first: NormalSolver | NormalSolver3 | None = None,
) -> list[float]:
    """J+ dx on the active joints with joint clamping [rad], 5 floats."""
    dq = [0.0] * 5
    free = list(active)
    err = list(error)
    inverse = first or solver(cols, free)
    while free:
        step = _capped(inverse.apply(err), max_step)
        out = [
            k
            for k, d in zip(free, step, strict=True)
            if not lower[k] <= q[k] + d <= upper[k]
        ]
        if not out:
            for k, d in zip(free, step, strict=True):
                dq[k] = d
            break
        for k, d in zip(free, step, strict=True):
            if k in out:
                dq[k] = min(max(q[k] + d, lower[k]), upper[k]) - q[k]
                c = cols[k]
                err = [e - c[i] * dq[k] for i, e in enumerate(err)]
        free = [k for k in free if k not in out]
        inverse = solver(cols, free) if free else inverse
    return dq


def null_step(
    q: Sequence[float],
    cols: Columns,
    gradient: Sequence[float],
    active: Sequence[int],
    lower: Sequence[float],
    upper: Sequence[float],
    alpha: float,
    max_step: float,
    first: NormalSolver | NormalSolver3 | None = None,
    margin: float = 0.0,
) -> Step:
    """-alpha (I - J+ J) grad H, shortened or re-projected to stay in range.

    ``margin`` [rad]: joints moving towards a limit closer than this slow
    the step down smoothly (see the module docstring).
    """
    free = list(active)
    inverse = first or solver(cols, free)
    while free:
        back = inverse.apply(inverse.times(gradient))
        null = [gradient[k] - b for k, b in zip(free, back, strict=True)]
        step = _capped([-alpha * n for n in null], max_step)
        fraction = 1.0
        blocked = []
        for k, d in zip(free, step, strict=True):
            room = _room(q[k], d, lower[k], upper[k])
            if margin > 0.0:
                room = min(room, _ease(q[k], d, lower[k], upper[k], margin))
            if room <= BLOCKED:
                blocked.append(k)
            fraction = min(fraction, room)
        if fraction > BLOCKED or not any(null):
            dq, projected = [0.0] * 5, [0.0] * 5
            for k, d, n in zip(free, step, null, strict=True):
                dq[k], projected[k] = fraction * d, n
            return Step(dq, projected, tuple(free))
        free = [k for k in free if k not in blocked]
        inverse = solver(cols, free) if free else inverse
    return Step([0.0] * 5, [0.0] * 5, ())


def _ease(q: float, step: float, low: float, high: float, margin: float) -> float:
    """smoothstep(distance to the limit ahead / margin), 1 beyond the margin."""
    if step == 0.0:
        return 1.0
    distance = (high - q) if step > 0.0 else (q - low)
    t = min(max(distance / margin, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def _room(q: float, step: float, low: float, high: float) -> float:
    """The fraction of ``step`` a joint can take before its limit, in [0, inf)."""
    if step > 0.0:
        return max((high - q) / step, 0.0)
    if step < 0.0:
        return max((low - q) / step, 0.0)
    return float("inf")


def gpm_step(
    q: Sequence[float],
    error: Sequence[float],
    cols: Columns,
    gradient: Sequence[float],
    active: Sequence[int],
    lower: Sequence[float],
    upper: Sequence[float],
    alpha: float,
    max_step: float,
    max_null_step: float,
    margin: float = 0.0,
) -> Step:
    """One step of eq. 14 on the active joints, within the joint limits.

    Args:
        q: Current joint angles [rad], 5 values.
        error: Task error to remove this step (dx), m values.
        cols: Task Jacobian by columns: one sequence of m values per joint (5).
        gradient: dH/dq, 5 values.
        active: Indices of the joints allowed to move.
        lower: Lower joint limits [rad], 5 values.
        upper: Upper joint limits [rad], 5 values.
        alpha: Null-space gain [rad^2 per unit of H].
        max_step: Largest change of any joint by the task part [rad].
        max_null_step: Largest change of any joint by the null-space part [rad].
        margin: Distance to a limit below which a joint moving towards it
            slows the null-space part down smoothly [rad]; 0: no slowing.

    Returns:
        The step; q + dq lies within the limits.
    """
    inverse = solver(cols, active)
    task = task_step(q, error, cols, active, lower, upper, max_step, inverse)
    moved = [a + b for a, b in zip(q, task, strict=True)]
    null = null_step(
        moved,
        cols,
        gradient,
        active,
        lower,
        upper,
        alpha,
        max_null_step,
        inverse,
        margin,
    )
    return null._replace(dq=[a + b for a, b in zip(task, null.dq, strict=True)])
