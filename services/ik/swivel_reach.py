"""How far S_R E_P W_R swivelled the elbow towards its goal, and why it stopped.

The function primitive holds the wrist and swivels the elbow round it by
descending ``SwivelGoal`` in the null space (eq. 14). A joint limit can stop
that motion short of the goal: the posture then rests on the limit
(``services.ik.gpm``) with the wrist still on its target, which used to read
as a plain success.

Tolerance: as phi changes the elbow moves on a circle of radius r, its
distance from the shoulder-wrist line, so a swivel error d_phi leaves the
elbow ``2 r sin(|d_phi| / 2)`` from where the goal puts it. That distance is
held to the solver's position tolerance (``TOLERANCE``, 0.1 mm), the accuracy
the wrist is held to: the elbow is what the primitive places (to clear an
obstacle), and a swivel error in radians would mean millimetres on a bent
arm and nothing on a nearly straight one.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from services.ik.iterate import TOLERANCE
from services.ik.kernel.chain import chain_for
from services.ik.measures.swivel_goal import wrap
from shared.errors import SwivelNotReachedError
from shared.geometry.swivel import elbow_offset_and_gradient, swivel_angle
from shared.robot.arm_model import ArmModel

#: A joint nearer than this to a bound is on it [rad]: null-space steps that
#: approach a bound end within 1e-7 rad of it.
ON_LIMIT = 1e-6


class SwivelReach(NamedTuple):
    """Where the elbow swivelled to, against its goal.

    Attributes:
        goal: Swivel angle asked [rad].
        reached: Swivel angle reached [rad], in [0, 2 pi).
        shortfall: ``reached - goal`` wrapped into [-pi, pi) [rad].
        elbow_miss: Distance of the elbow from where the goal puts it [m].
    """

    goal: float
    reached: float
    shortfall: float
    elbow_miss: float


def swivel_reach(arm: ArmModel, q: np.ndarray, goal: float) -> SwivelReach:
    """The swivel of posture ``q`` [rad], shape (5,), against ``goal`` [rad]."""
    o = chain_for(arm).state(q).origins
    reached = swivel_angle(o[0], o[2], o[4])
    shortfall = wrap(reached - goal)
    r2 = elbow_offset_and_gradient(o[0], o[2], o[4], [], [])[0]
    miss = 2.0 * math.sqrt(r2) * math.sin(0.5 * abs(shortfall))
    return SwivelReach(goal, reached, shortfall, miss)


def check_swivel(
    arm: ArmModel, active: tuple[int, ...], q: np.ndarray, goal: float
) -> float:
    """The swivel reached by ``q`` [rad]; raise if the elbow stopped short.

    Args:
        arm: The arm.
        active: Indices of the joints the primitive moves.
        q: The solved posture [rad], shape (5,).
        goal: The swivel asked [rad].

    Raises:
        SwivelNotReachedError: the elbow is more than ``TOLERANCE`` from where
            the goal puts it, naming the active joint on its limit, if any.
    """
    reach = swivel_reach(arm, q, goal)
    if reach.elbow_miss <= TOLERANCE:
        return reach.reached
    joint, limit = _on_limit(arm, active, q)
    raise SwivelNotReachedError(
        goal,
        reach.reached,
        shortfall=reach.shortfall,
        elbow_miss=reach.elbow_miss,
        joints=dict(zip(arm.joint_names, (float(v) for v in q), strict=True)),
        joint=joint,
        limit=limit,
    )


def _on_limit(
    arm: ArmModel, active: tuple[int, ...], q: np.ndarray
) -> tuple[str, float | None]:
    """(NAO name, bound [rad]) of the active joint nearest a bound, if on one."""
    lower, upper = arm.limits.lower, arm.limits.upper
    gaps = [(min(q[k] - lower[k], upper[k] - q[k]), k) for k in active]
    gap, k = min(gaps)
    if gap > ON_LIMIT:
        return "", None
    bound = lower[k] if q[k] - lower[k] <= upper[k] - q[k] else upper[k]
    return arm.joint_names[k], float(bound)
