"""The decision at one path point, from the arm's state there (the hot path).

``decide_point`` is what the IK tracker's chooser calls once per path
point: the five motion variables from the arm's kinematics and the goal
(``services.fit.variables.variables_at``), then the compiled model
(``Decider``). No pydantic and no numpy on the way unless a palm direction
is wanted; the message (``Decision``) is built later, only if asked.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from services.decide.decider import Choice, Decider
from services.fit.roll import roll_to_go_at
from services.fit.variables import Vec3, variables_at
from services.ik.kernel.chain import ChainState
from shared.robot.arm_model import ArmModel, Kinematics


class DecidingArm(NamedTuple):
    """The deciding arm's segment lengths and side (the variables' scale).

    Attributes:
        upper_arm: Shoulder-to-elbow length L_u [m].
        forearm: Elbow-to-wrist length L_f [m].
        sign: +1 for the right arm, -1 for the left (the palm's side).
    """

    upper_arm: float
    forearm: float
    sign: float

    @classmethod
    def of(cls, arm: ArmModel) -> DecidingArm:
        """The lengths and side of ``arm``."""
        return cls(arm.upper_arm_length, arm.forearm_length, arm.side.sign)


def decide_point(
    decider: Decider,
    kin: Kinematics | ChainState,
    goal: tuple[float, float, float],
    size: DecidingArm,
    palm: Sequence[float] | None = None,
    previous: Choice | None = None,
) -> Choice:
    """The primitive for the point where the arm is at ``kin`` (eq. 10).

    Args:
        decider: The compiled motion model.
        kin: The arm's kinematics at this point: ``Kinematics``, or the IK
            tracker's state that reads like it (its float fields are used).
        goal: Where the wrist is going, torso frame [m].
        size: The arm's lengths and side.
        palm: Wanted palm direction at the goal (unit; 3 floats are fastest),
            or ``None`` (W_R then unobserved).
        previous: The decision at the point before, ``None`` at the start.

    Returns:
        The winner and every g.
    """
    shoulder, elbow, wrist = _points(kin)
    roll = 0.0
    if palm is not None:
        axis = _palm_axis(kin)
        wanted = (size.sign * palm[0], size.sign * palm[1], size.sign * palm[2])
        roll = roll_to_go_at(
            shoulder, elbow, wrist, axis, goal, wanted, size.upper_arm, size.forearm
        )
    values = variables_at(
        shoulder, elbow, wrist, goal, size.upper_arm, size.forearm, roll
    )
    state = None if previous is None else previous.state
    return decider.decide(values, palm is not None, state)


def _points(kin: Kinematics | ChainState) -> tuple[Vec3, Vec3, Vec3]:
    """Shoulder, elbow and wrist as float tuples; the tracker's state has them so."""
    if isinstance(kin, ChainState):
        return kin.p_shoulder, kin.p_elbow, kin.p_wrist
    return _vec3(kin.shoulder), _vec3(kin.elbow), _vec3(kin.wrist)


def _vec3(v: np.ndarray) -> Vec3:
    return (float(v[0]), float(v[1]), float(v[2]))


def _palm_axis(kin: Kinematics | ChainState) -> Sequence[float]:
    """The wrist frame's y axis (its rotation's second column) as floats."""
    if isinstance(kin, ChainState):
        rows = kin.rot
        return (rows[0][1], rows[1][1], rows[2][1])
    return kin.wrist_rotation[:, 1].tolist()
