"""The gradient projection method (paper eq. 14) on a primitive's active joints.

    dq = J+ dx - alpha (I - J+ J) grad H

(the paper writes +k with k < 0 to descend H). One SVD of J gives both parts:
J+ is damped below singular value ``DAMPING`` so that singular directions (a
stretched arm, or the radial direction that S_R E_P W_P cannot move) stay
bounded, and the null-space projector is exact, keeping the singular
directions whose value falls below ``RANK_CUT`` out of the task's row space.

Joint limits are kept by each priority in turn, so no step ever leaves them:
    1. The task step J+ dx uses joint clamping: a joint it would push out of
       range stops at the limit and the others solve the remaining error.
    2. The null-space step is shortened so that no joint crosses a limit; a
       joint already on a limit that the null-space motion would push further
       is dropped from that motion, which is projected again without it.
       When H's optimum lies beyond a limit this leaves the posture on the
       limit: the optimum within the range.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.robot.limits import JointLimits

#: Damping of the pseudo-inverse [m]: below this singular value J+ fades out.
DAMPING = 1e-3
#: Singular values below this count as zero for the null-space projector [m].
RANK_CUT = 1e-6
#: A null-space step shorter than this fraction counts as blocked by a limit.
BLOCKED = 1e-6


class Step(NamedTuple):
    """Result of one GPM step.

    Attributes:
        dq: Joint change [rad], shape (5,), zero outside the active joints.
        projected_gradient: The gradient of H projected on the null space of
            the joints the null-space motion used, zero elsewhere, shape (5,):
            zero at an optimum within the limits.
        null_joints: Indices of the joints the null-space motion used.
    """

    dq: np.ndarray
    projected_gradient: np.ndarray
    null_joints: tuple[int, ...]


class Decomposition(NamedTuple):
    """Damped pseudo-inverse and exact null-space projector of one Jacobian."""

    pinv: np.ndarray
    null: np.ndarray


def decompose(jac: np.ndarray) -> Decomposition:
    """J+ (damped, shape (n, m)) and I - J+J (exact, shape (n, n)) for J (m, n)."""
    u, s, vt = np.linalg.svd(jac, full_matrices=True)
    k = s.size
    pinv = (vt[:k].T * (s / (s * s + DAMPING**2))) @ u[:, :k].T
    rank = int(np.count_nonzero(s > RANK_CUT))
    row = vt[:rank]
    return Decomposition(pinv, np.eye(jac.shape[1]) - row.T @ row)


def damped_pinv(jac: np.ndarray) -> np.ndarray:
    """The damped pseudo-inverse of J, shape (n, m)."""
    return decompose(jac).pinv


def _capped(step: np.ndarray, largest: float) -> np.ndarray:
    """``step`` scaled down so that no entry exceeds ``largest`` in size."""
    biggest = float(np.max(np.abs(step), initial=0.0))
    return step * (largest / biggest) if biggest > largest else step


def task_step(
    q: np.ndarray,
    error: np.ndarray,
    jacobian: np.ndarray,
    active: np.ndarray,
    limits: JointLimits,
    max_step: float,
) -> np.ndarray:
    """J+ dx on the active joints with joint clamping [rad], shape (5,)."""
    dq = np.zeros_like(q)
    free = np.asarray(active, dtype=int)
    err = np.asarray(error, dtype=float).copy()
    while free.size:
        step = _capped(damped_pinv(jacobian[:, free]) @ err, max_step)
        trial = q[free] + step
        out = (trial < limits.lower[free]) | (trial > limits.upper[free])
        if not out.any():
            dq[free] = step
            break
        stopped = free[out]
        dq[stopped] = np.clip(trial[out], limits.lower[stopped], limits.upper[stopped])
        dq[stopped] -= q[stopped]
        err -= jacobian[:, stopped] @ dq[stopped]
        free = free[~out]
    return dq


def _room(
    q: np.ndarray, step: np.ndarray, low: np.ndarray, high: np.ndarray
) -> np.ndarray:
    """Per joint, the fraction of ``step`` it can take before a limit, in [0, inf)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        room = np.where(
            step > 0, (high - q) / step, np.where(step < 0, (low - q) / step, np.inf)
        )
    return np.maximum(room, 0.0)


def null_step(
    q: np.ndarray,
    jacobian: np.ndarray,
    gradient: np.ndarray,
    active: np.ndarray,
    limits: JointLimits,
    alpha: float,
    max_step: float,
) -> Step:
    """-alpha (I - J+ J) grad H, shortened or re-projected to stay in range."""
    dq, projected = np.zeros_like(q), np.zeros_like(q)
    free = np.asarray(active, dtype=int)
    while free.size:
        null = decompose(jacobian[:, free]).null @ gradient[free]
        step = _capped(-alpha * null, max_step)
        room = _room(q[free], step, limits.lower[free], limits.upper[free])
        fraction = min(1.0, float(room.min()))
        if fraction > BLOCKED or not np.any(null):
            dq[free], projected[free] = fraction * step, null
            break
        free = free[room > BLOCKED]
    return Step(dq, projected, tuple(int(i) for i in free))


def gpm_step(
    q: np.ndarray,
    error: np.ndarray,
    jacobian: np.ndarray,
    gradient: np.ndarray,
    active: np.ndarray,
    limits: JointLimits,
    alpha: float,
    max_step: float,
    max_null_step: float,
) -> Step:
    """One step of eq. 14 on the active joints, within the joint limits.

    Args:
        q: Current joint angles [rad], shape (5,).
        error: Task error to remove this step (dx), shape (m,).
        jacobian: Task Jacobian over all joints, shape (m, 5).
        gradient: dH/dq over all joints, shape (5,).
        active: Indices of the joints allowed to move, shape (k,).
        limits: Joint ranges.
        alpha: Null-space gain [rad^2 per unit of H].
        max_step: Largest change of any joint by the task part [rad].
        max_null_step: Largest change of any joint by the null-space part [rad].

    Returns:
        The step; q + dq lies within the limits.
    """
    active = np.asarray(active, dtype=int)
    task = task_step(q, error, jacobian, active, limits, max_step)
    null = null_step(q + task, jacobian, gradient, active, limits, alpha, max_null_step)
    return null._replace(dq=task + null.dq)
