"""A path-tracking step of eq. 14 in a joint metric: smooth at limits and switches.

    dq = W^1/2 Jw+ dx - alpha W^1/2 (I - Jw+ Jw) W^1/2 grad H,   Jw = J W^1/2

W = diag(w) weighs how freely each joint moves: the step is the one of least
sum(dq_k^2 / w_k) that does the task (weighted least norm, Whitney 1969;
Chan and Dubey 1995 for limits). Two things set w:

    - The primitive: its active joints have w = 1, the others ``LOCKED``
      (0.1: moving one of them costs ten times as much), or
      ``LOCKED_TURNING`` (0.25) where the task also turns the palm.
      A locked joint thus moves only in the part of the task the active
      joints cannot do at all (a shoulder swing cannot change the hand's
      distance from the shoulder), and then as little as it can: the wrist
      stays on the path instead of falling behind it and jumping back.
    - The limits: a joint moving towards a limit closer than ``margin``
      has its w lowered smoothly, down to ``FLOOR`` (:func:`limit_weight`,
      from the direction and size of the step it would take without this),
      so the other joints take over its share gradually. With plain joint
      clamping (:mod:`services.ik.gpm`) the joint stops dead on the limit
      and the others jump to make up for it: a kink the timing must slow
      the whole movement down for.

Every w is a smooth function of the posture, so the joint path is smooth
where the wrist path is. The null-space part descends H with the active
joints only, in the same metric, and only if they outnumber the task's rows:
with as many active joints as rows (S_R E_P W_PR turning the palm: four of
each) there is no null space, except at a posture where the active columns
lose rank. There the inverse is damped near the singularity, its projector
is no longer zero and the gradient leaks into the task's weak direction, on
and off as the damping switches: with ElbowYaw crossing 0 that made a
sawtooth in ElbowYaw that slowed the whole reach to several times its
human duration. The result is clipped to the joint range as a last guard
(the weights keep steps off the limits, so this rarely acts).
"""

from __future__ import annotations

import math
from typing import Final

from services.ik.gpm import SINGULAR_DAMPING
from services.ik.kernel.small import factor3, normal_solver, solve3

#: Task Jacobian by columns, one tuple of m values per joint (concrete types:
#: compiled, a list and a tuple index faster than any Sequence).
Cols = list[tuple[float, ...]]
#: Weight of a joint the primitive does not move.
LOCKED: Final = 0.1
#: The same where the task also turns the palm (a fourth row, the roll):
#: there, with 0.1, a roll WristYaw cannot make (the people hold it at its
#: limit) falls on the primitive's own shoulder joints, mostly ElbowYaw,
#: instead of being shared by the arm. Chosen on the demonstrations the
#: shipped motion model was fitted on: ``armplan experiment similarity
#: --palm --seed 0``, mp's mean posture similarity S (eq. 22-23) to the
#: subjects' for 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.5 and 1: 0.9499,
#: 0.9724, 0.9773, 0.97907, 0.97914, 0.9786, 0.9776, 0.9781 (least-norm
#: 0.9758, single 0.9764); the best, 0.25, is taken.
LOCKED_TURNING: Final = 0.25
#: Damping of the weighted solve [m^2]: a joint that barely moves the
#: wrist (ElbowYaw of a straight arm) must not take huge steps for it.
DAMPING: Final = 1e-6
#: Share of the largest joint step above which a joint counts as fully moving.
MOVING: Final = 0.1
#: Every joint's index.
_ALL: Final = (0, 1, 2, 3, 4)
_EVERY: Final[list[int]] = [0, 1, 2, 3, 4]
#: Smallest weight a joint on its limit keeps.
FLOOR: Final = 1e-4


def limit_weight(
    q: float, share: float, low: float, high: float, margin: float
) -> float:
    """Weight in [FLOOR, 1] of a joint at ``q`` [rad] about to move.

    ``share`` is its step over the largest joint step (signed, in [-1, 1]).
    The weight is 1 - (1 - smoothstep(distance / margin)) *
    smoothstep(|share| / MOVING), with the distance to the limit the joint
    moves towards: 1 for a joint that barely takes part in the step or is
    farther than ``margin`` from that limit, lower the closer it is. Both
    factors are smooth, so the weight changes smoothly even where the joint
    turns round; the share does not depend on the step's size, so the
    weights hold as the hand slows down to the goal.
    """
    if share == 0.0 or margin <= 0.0:
        return 1.0
    distance = (high - q) if share > 0.0 else (q - low)
    near = 1.0 - _smoothstep(distance / margin)
    moving = _smoothstep(abs(share) / MOVING)
    return max(1.0 - near * moving, FLOOR)


def _smoothstep(x: float) -> float:
    t = min(max(x, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def weighted_step(
    q: list[float],
    error: list[float],
    cols: Cols,
    gradient: list[float],
    base: list[float],
    lower: list[float],
    upper: list[float],
    alpha: float,
    max_step: float,
    max_null_step: float,
    margin: float,
) -> list[float]:
    """One step towards the task, 5 floats [rad].

    Args:
        q: Joint angles [rad], 5 values.
        error: Task error to remove (dx), m values.
        cols: Task Jacobian by columns, 5 sequences of m values.
        gradient: dH/dq, 5 values.
        base: The primitive's weight per joint (1 active, ``LOCKED`` not).
        lower: Lower joint limits [rad], 5 values.
        upper: Upper joint limits [rad], 5 values.
        alpha: Null-space gain [rad^2 per unit of H].
        max_step: Largest change of a joint by the task part [rad].
        max_null_step: Largest change of a joint by the null-space part [rad].
        margin: Distance to a limit where a joint starts to give way [rad].

    Returns:
        dq, with q + dq within the limits.
    """
    three = len(cols[0]) == 3
    task, null = _parts(three, error, cols, gradient, base, base, alpha)
    if _near_a_limit(q, lower, upper, margin):
        # the weights depend on where the step goes
        free = [task[k] + null[k] for k in range(5)]
        size = _largest(free) or 1.0
        weights = [
            b * limit_weight(q[k], free[k] / size, lower[k], upper[k], margin)
            for k, b in enumerate(base)
        ]
        if weights != base:
            task, null = _parts(three, error, cols, gradient, weights, base, alpha)
    task, null = _capped(task, max_step), _capped(null, max_null_step)
    return [
        min(max(q[k] + task[k] + null[k], lower[k]), upper[k]) - q[k] for k in range(5)
    ]


def _near_a_limit(
    q: list[float], lower: list[float], upper: list[float], margin: float
) -> bool:
    """True if a joint is closer than ``margin`` to one of its limits."""
    # A loop, not any(generator): compiled (mypyc) it runs without objects.
    for k in range(5):  # noqa: SIM110
        if q[k] - lower[k] < margin or upper[k] - q[k] < margin:
            return True
    return False


def _parts(
    three: bool,
    error: list[float],
    cols: Cols,
    gradient: list[float],
    weights: list[float],
    base: list[float],
    alpha: float,
) -> tuple[list[float], list[float]]:
    """The task and null-space parts: :func:`_parts3` for a three-row task."""
    if three:
        return _parts3(error, cols, gradient, weights, base, alpha)
    return _parts_general(error, cols, gradient, weights, base, alpha)


def _parts_general(
    error: list[float],
    cols: Cols,
    gradient: list[float],
    weights: list[float],
    base: list[float],
    alpha: float,
) -> tuple[list[float], list[float]]:
    """The task part W^1/2 Jw+ dx and the null-space part, 5 floats each.

    The null-space part is -alpha W^1/2 (I - Jw+ Jw) W^1/2 grad H over the
    active joints (``base`` 1), zero unless they outnumber the rows. When
    every joint is active it reuses the task's factorisation: its damping
    (``DAMPING``) leaks a negligible DAMPING / sigma^2 of the gradient into
    the task, which the next step removes anyway. Any number of task rows,
    through ``normal_solver``.
    """
    roots = [math.sqrt(w) for w in weights]
    scaled = [(c[0] * r, c[1] * r, c[2] * r) if len(c) == 3 else [v * r for v in c]
              for c, r in zip(cols, roots, strict=True)]  # fmt: skip
    inverse = normal_solver(scaled, _ALL, DAMPING, SINGULAR_DAMPING)
    task = [r * v for r, v in zip(roots, inverse.apply(error), strict=True)]
    active = [k for k in range(5) if base[k] == 1.0]
    if alpha == 0.0 or len(active) <= len(error):
        return task, [0.0] * 5
    if len(active) < 5:
        inverse = normal_solver(scaled, active, 0.0, SINGULAR_DAMPING)
    g = [0.0] * 5
    for k in active:
        g[k] = roots[k] * gradient[k]
    back = inverse.apply(inverse.times(g))
    null = [0.0] * 5
    for k, b in zip(active, back, strict=True):
        null[k] = -alpha * roots[k] * (g[k] - b)
    return task, null


def _parts3(
    error: list[float],
    cols: Cols,
    gradient: list[float],
    weights: list[float],
    base: list[float],
    alpha: float,
) -> tuple[list[float], list[float]]:
    """:func:`_parts_general` for a three-row task (the wrist position), unrolled.

    The same arithmetic in the same order as the general path through
    ``normal_solver`` (so the same bits), without its intermediate objects:
    this runs once or twice per path point.
    """
    roots = [math.sqrt(w) for w in weights]
    sx, sy, sz = [0.0] * 5, [0.0] * 5, [0.0] * 5
    for k in range(5):
        c, r = cols[k], roots[k]
        sx[k], sy[k], sz[k] = c[0] * r, c[1] * r, c[2] * r
    low = factor3(sx, sy, sz, _EVERY, DAMPING, SINGULAR_DAMPING)
    x0, x1, x2 = solve3(low, error[0], error[1], error[2])
    task = [roots[k] * (sx[k] * x0 + sy[k] * x1 + sz[k] * x2) for k in range(5)]
    null = [0.0] * 5
    active = [k for k in range(5) if base[k] == 1.0]
    if alpha == 0.0 or len(active) <= 3:
        return task, null
    if len(active) < 5:
        low = factor3(sx, sy, sz, active, 0.0, SINGULAR_DAMPING)
    g = [0.0] * 5
    o0 = o1 = o2 = 0.0
    for k in active:
        gk = g[k] = roots[k] * gradient[k]
        o0 += sx[k] * gk
        o1 += sy[k] * gk
        o2 += sz[k] * gk
    x0, x1, x2 = solve3(low, o0, o1, o2)
    for k in active:
        back = sx[k] * x0 + sy[k] * x1 + sz[k] * x2
        null[k] = -alpha * roots[k] * (g[k] - back)
    return task, null


def _capped(step: list[float], largest: float) -> list[float]:
    biggest = _largest(step)
    return step if biggest <= largest else [v * largest / biggest for v in step]


def _largest(values: list[float]) -> float:
    """max |v| over ``values``."""
    top = 0.0
    for v in values:
        top = max(top, abs(v))
    return top


__all__ = ["FLOOR", "LOCKED", "LOCKED_TURNING", "limit_weight", "weighted_step"]
