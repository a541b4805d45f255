"""The wrist task of an IK step: its error and Jacobian for one posture."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.geometry.palm import roll_error
from shared.robot.arm_model import Kinematics


class WristTask(NamedTuple):
    """Put the wrist on ``position`` and, optionally, turn the palm to ``palm``.

    With ``radial`` False the task controls only the wrist's direction from
    the shoulder, not its distance: the error and Jacobian are projected on
    the plane normal to the shoulder-wrist line. That is the task of the
    primitives in which the shoulder swings an arm of fixed shape (S_R E_P
    W_P, S_R E_P W_PR): ElbowRoll is passive, so the distance is too.

    Attributes:
        position: Wanted wrist position in the torso frame [m], shape (3,).
        palm: Wanted palm direction (unit, shape (3,)) or ``None``.
        sign: +1 for the right hand, -1 for the left (palm side).
        radial: Whether the distance from the shoulder is controlled.
    """

    position: np.ndarray
    palm: np.ndarray | None
    sign: float
    radial: bool = True

    def residual(self, kin: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        """(error, Jacobian) of the task at ``kin``.

        Returns:
            error: Position error [m] (3,), then roll error [rad] if a palm
                direction is wanted; shape (m,), m = 3 or 4.
            jacobian: d(task)/dq, shape (m, 5); the roll row is the wrist's
                angular Jacobian projected on the forearm axis.
        """
        err, jac = self.position - kin.wrist, kin.wrist_jacobian
        if not self.radial:
            out = kin.wrist - kin.shoulder
            out /= np.linalg.norm(out)
            tangent = np.eye(3) - np.outer(out, out)
            err, jac = tangent @ err, tangent @ jac
        if self.palm is None:
            return err, jac
        roll = roll_error(kin.wrist_rotation, self.sign, self.palm)
        axis = kin.wrist_rotation[:, 0]
        row = axis @ kin.wrist_angular_jacobian
        return np.append(err, roll), np.vstack((jac, row))

    def position_error(self, kin: Kinematics) -> float:
        """Distance from the wrist to ``position`` [m] (radial part included)."""
        return float(np.linalg.norm(self.position - kin.wrist))

    def palm_error(self, kin: Kinematics) -> float:
        """Absolute roll still needed to face the palm [rad] (0 without a palm)."""
        if self.palm is None:
            return 0.0
        return abs(roll_error(kin.wrist_rotation, self.sign, self.palm))


def controls_radius(active: tuple[int, ...]) -> bool:
    """False when the shoulder swings an arm of fixed shape (ElbowRoll passive).

    Such primitives (S_R E_P W_P, S_R E_P W_PR) move the wrist with the
    shoulder joints alone: they control its direction from the shoulder, not
    its distance.
    """
    joints = set(active)
    return not ({0, 1} <= joints and 3 not in joints)
