"""NAO joint angles from retargeted arm points: the human posture on NAO.

A retargeted human posture is given as points (elbow, wrist, in NAO's torso
frame, at NAO's segment lengths) and, where the data have it, the wrist
frame. It becomes NAO joint angles in two steps, because WristYaw moves
neither the elbow nor the wrist (the wrist is its origin):

1. the four arm joints put NAO's elbow and wrist on the points: in closed
   form where the points are at NAO's lengths and the posture within the
   robot file's ranges (``shared.robot.elbow_wrist_joints``), else by
   bounded least squares on (elbow error [m], wrist error [m]) (scipy's
   trust-region reflective solver, given the points' Jacobians), so they
   stay within the ranges;
2. WristYaw turns the palm normal nearest the human one, in closed form,
   if a frame is given (else it keeps its warm start).

Where a human posture lies outside NAO's ranges the nearest one within them
is returned. A sequence is solved sample by sample, each warm-started from
the one before, so the angles are continuous.
"""

from __future__ import annotations

import math

import numpy as np

from shared.errors import InvalidInputError
from shared.robot.arm_model import ArmModel
from shared.robot.elbow_wrist_joints import elbow_wrist_joints
from shared.robot.postures import rest

#: The arm joints that place elbow and wrist, and the wrist's own joint.
ARM, WRIST_YAW = slice(0, 4), 4


def joints_from_points(
    arm: ArmModel,
    elbow: np.ndarray,
    wrist: np.ndarray,
    palm: np.ndarray | None = None,
    guess: np.ndarray | None = None,
) -> np.ndarray:
    """Joint angles [rad], shape (5,), putting NAO's arm on the points.

    Args:
        arm: The NAO arm.
        elbow: Elbow position in the torso frame [m], shape (3,).
        wrist: Wrist position in the torso frame [m], shape (3,).
        palm: Palm normal (wrist frame's y axis), shape (3,), or ``None``.
        guess: Warm start [rad], shape (5,); default the arm at rest.

    Raises:
        InvalidInputError: if a point is not finite.
    """
    for name, value in (("elbow", elbow), ("wrist", wrist)):
        if not np.all(np.isfinite(value)):
            raise InvalidInputError(
                f"{name} position {value} is not finite", field=name
            )
    lower, upper = arm.limits.lower, arm.limits.upper
    q = rest(arm.side) if guess is None else np.asarray(guess, dtype=float)
    q = np.clip(q, lower + 1e-9, upper - 1e-9)
    exact = elbow_wrist_joints(arm, elbow, wrist, q)
    if exact is not None:
        return _with_palm(arm, np.concatenate((exact, q[WRIST_YAW:])), palm)

    def point_error(joints: np.ndarray) -> np.ndarray:
        points = arm.fk(np.concatenate((joints, q[WRIST_YAW:])))
        return np.concatenate((points.elbow - elbow, points.wrist - wrist))

    def point_jacobian(joints: np.ndarray) -> np.ndarray:
        """d(point_error)/d(joints) [m/rad], shape (6, 4)."""
        posture = np.concatenate((joints, q[WRIST_YAW:]))
        return np.vstack(
            [arm.jacobian(posture, point)[:, ARM] for point in ("elbow", "wrist")]
        )

    # Imported here: scipy.optimize takes about 0.6 s to import, and the IK
    # (``armplan ik``, the ik service) imports this module for its elbow
    # turns, which mostly have a closed form.
    from scipy.optimize import least_squares  # type: ignore[import-untyped]

    fit = least_squares(
        point_error,
        q[ARM],
        jac=point_jacobian,
        bounds=(lower[ARM], upper[ARM]),
        xtol=1e-12,
    )
    return _with_palm(arm, np.concatenate((fit.x, q[WRIST_YAW:])), palm)


def _with_palm(arm: ArmModel, q: np.ndarray, palm: np.ndarray | None) -> np.ndarray:
    """Posture ``q`` [rad], (5,), its WristYaw turned to ``palm`` if one is given."""
    if palm is not None:
        q[WRIST_YAW] = wrist_yaw_for_palm(arm, q, palm)
    return q


def wrist_yaw_for_palm(arm: ArmModel, q: np.ndarray, palm: np.ndarray) -> float:
    """The WristYaw [rad] within its range that turns the palm nearest ``palm``.

    WristYaw turns the wrist frame about its x axis, so with y0, z0 the
    frame's axes at yaw 0 the palm normal is cos(t) y0 + sin(t) z0, closest
    to ``palm`` at t* = atan2(palm . z0, palm . y0), an angle known only up
    to whole turns. With t* outside the range, its turn nearest the present
    yaw is clipped to the range: from the range's middle that is the limit
    on the side the palm is beyond (the nearer palm), and from a limit the
    wrist waits there until the palm comes back into range, rather than
    swinging over its whole range to the other limit. The rule is the same
    for both arms turned mirror-wise (yaw and palm angle change sign).

    Args:
        arm: The NAO arm.
        q: Posture [rad], shape (5,); its WristYaw is the present yaw.
        palm: Wanted palm normal, shape (3,).
    """
    zero = np.concatenate((q[ARM], [0.0]))
    frame = arm.rotation(zero, "wrist")
    best = math.atan2(float(palm @ frame[:, 2]), float(palm @ frame[:, 1]))
    low, high = float(arm.limits.lower[WRIST_YAW]), float(arm.limits.upper[WRIST_YAW])
    if low <= best <= high:
        return best
    present = float(q[WRIST_YAW])
    turns = round((present - best) / math.tau)  # half a turn: to even, +- alike
    return min(max(best + turns * math.tau, low), high)


def joint_path_from_points(
    arm: ArmModel,
    elbow: np.ndarray,
    wrist: np.ndarray,
    frames: np.ndarray | None = None,
    guess: np.ndarray | None = None,
) -> np.ndarray:
    """:func:`joint_path_from_palms` given whole wrist frames, shape (n, 3, 3).

    Their y axes are the palm normals; ``frames`` ``None`` means no palm.
    """
    palms = None if frames is None else np.asarray(frames)[:, :, 1]
    return joint_path_from_palms(arm, elbow, wrist, palms, guess)


def joint_path_from_palms(
    arm: ArmModel,
    elbow: np.ndarray,
    wrist: np.ndarray,
    palms: np.ndarray | None = None,
    guess: np.ndarray | None = None,
) -> np.ndarray:
    """Joint angles [rad], shape (n, 5), for n retargeted postures, warm-started.

    Each sample starts from the one before (the first from ``guess``).

    Args:
        arm: The NAO arm.
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        palms: Palm normals (wrist frame's y axis), shape (n, 3), or ``None``.
        guess: Warm start of the first sample [rad], shape (5,).
    """
    q = rest(arm.side) if guess is None else np.asarray(guess, dtype=float)
    out = []
    for k in range(len(elbow)):
        palm = None if palms is None else palms[k]
        q = joints_from_points(arm, elbow[k], wrist[k], palm, q)
        out.append(q)
    return np.array(out)
