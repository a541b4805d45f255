"""Closed-form IK of the one-joint primitives (paper eq. 11-13) and the wrist turn.

NAO's elbow sits 15 mm off the upper arm's axis, so the arm triangle of
eq. 11-12 is solved with that offset: with u the elbow offset in the
ShoulderRoll frame and L_f the forearm, the shoulder-to-wrist distance L_d
obeys

    L_d^2 = |u|^2 + L_f^2 + 2 L_f (u_x cos th4 + u_y cos th3 sin th4),

which for u_y = 0 is exactly eq. 11-12 (cos th4 = -cos Omega, th4 = pi - Omega).
For S_R W_P only ElbowYaw turns, swinging the wrist round the upper arm's axis
on a circle of radius r = L_f |sin th4| (eq. 13 takes r = L_f, the elbow at a
right angle): th3 changes by arccos((2 r^2 - L_w^2) / (2 r^2)), L_w the chord
from the start wrist to the target.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from shared.errors import InvalidInputError, PrimitiveCannotReachError
from shared.geometry.palm import roll_error
from shared.robot.arm_model import ArmModel

ELBOW_YAW, ELBOW_ROLL, WRIST_YAW = 2, 3, 4


class GeometricSolution(NamedTuple):
    """A closed-form posture and where its wrist ends up.

    Attributes:
        q: Joint angles [rad], shape (5,).
        wrist: Wrist position [m], shape (3,).
        residual: Distance from the wrist to the target [m].
    """

    q: np.ndarray
    wrist: np.ndarray
    residual: float


def triangle_elbow_angle(upper: float, forearm: float, distance: float) -> float:
    """ElbowRoll th4 = pi - Omega of the paper's arm triangle (eq. 11-12) [rad].

    Args:
        upper: Upper arm length L_u [m].
        forearm: Forearm length L_f [m].
        distance: Shoulder-to-wrist distance L_d [m].
    """
    cos_omega = (upper**2 + forearm**2 - distance**2) / (2.0 * upper * forearm)
    return math.pi - math.acos(min(max(cos_omega, -1.0), 1.0))


def elbow_roll_candidates(
    arm: ArmModel, elbow_yaw: float, distance: float
) -> list[float]:
    """ElbowRoll angles [rad] that put the wrist ``distance`` m from the shoulder.

    Solves A cos th4 + B sin th4 = C (module docstring); returns the roots
    within ElbowRoll's range, possibly none.
    """
    u, lf = arm.elbow_offset, arm.forearm_length
    a, b = float(u[0]), float(u[1] * math.cos(elbow_yaw))
    c = (distance**2 - float(u @ u) - lf**2) / (2.0 * lf)
    radius = math.hypot(a, b)
    if abs(c) > radius:
        return []
    base, spread = math.atan2(b, a), math.acos(c / radius)
    low, high = arm.limits.lower[ELBOW_ROLL], arm.limits.upper[ELBOW_ROLL]
    roots = {base + spread, base - spread}
    wrapped = [(r + math.pi) % (2.0 * math.pi) - math.pi for r in roots]
    return sorted(r for r in wrapped if low - 1e-12 <= r <= high + 1e-12)


def _finish(
    arm: ArmModel, q: np.ndarray, target: np.ndarray, name: str, reason: str, tol: float
) -> GeometricSolution:
    q = arm.limits.clip(q)
    wrist = arm.fk(q).wrist
    residual = float(np.linalg.norm(wrist - target))
    if residual > tol:
        raise PrimitiveCannotReachError(name, target, wrist, residual, reason)
    return GeometricSolution(q, wrist, residual)


def solve_elbow_triangle(
    arm: ArmModel, start: np.ndarray, target: np.ndarray, tol: float
) -> GeometricSolution:
    """E_R W_P: only ElbowRoll moves; the arm triangle fixes it (eq. 11-12).

    Args:
        arm: The arm.
        start: Start posture [rad], shape (5,); all but ElbowRoll are kept.
        target: Wrist target [m], shape (3,).
        tol: Largest accepted wrist error [m].

    Raises:
        PrimitiveCannotReachError: if no ElbowRoll in range puts the wrist on
            the target (the wrist only moves on a circle about the elbow).
    """
    q = np.array(start, dtype=float)
    shoulder = arm.fk(q).shoulder
    distance = float(np.linalg.norm(target - shoulder))
    roots = elbow_roll_candidates(arm, q[ELBOW_YAW], distance)
    reason = "only ElbowRoll moves, so the wrist stays on a circle about the elbow"
    if not roots:
        low, high = arm.limits.lower[ELBOW_ROLL], arm.limits.upper[ELBOW_ROLL]
        lengths = [_wrist_distance(arm, q, angle) for angle in (low, high)]
        q[ELBOW_ROLL] = (low, high)[
            int(np.argmin([abs(d - distance) for d in lengths]))
        ]
        return _finish(arm, q, target, "E_R W_P", reason + " out of this distance", tol)
    q[ELBOW_ROLL] = _best_root(arm, q, target, roots, tol)
    return _finish(arm, q, target, "E_R W_P", reason, tol)


def _best_root(
    arm: ArmModel, start: np.ndarray, target: np.ndarray, roots: list[float], tol: float
) -> float:
    """The ElbowRoll root [rad] whose wrist lands nearest ``target``.

    Both roots put the wrist at the target's distance from the shoulder, but
    only one of them, in general, on the target: with the elbow offset the
    distance is not monotonic in ElbowRoll near a straight arm, so the root
    nearest the start's ElbowRoll may be the wrong one. Roots within ``tol``
    [m] of the target count as equal; of those, the one nearest the start's
    ElbowRoll wins (the smallest move).
    """
    trial = np.array(start, dtype=float)

    def key(root: float) -> tuple[float, float]:
        trial[ELBOW_ROLL] = root
        miss = float(np.linalg.norm(arm.fk(trial).wrist - target))
        return max(miss - tol, 0.0), abs(root - start[ELBOW_ROLL])

    return min(roots, key=key)


def _wrist_distance(arm: ArmModel, q: np.ndarray, elbow_roll: float) -> float:
    trial = q.copy()
    trial[ELBOW_ROLL] = elbow_roll
    points = arm.fk(trial)
    return float(np.linalg.norm(points.wrist - points.shoulder))


def solve_shoulder_rotation(
    arm: ArmModel, start: np.ndarray, target: np.ndarray, tol: float
) -> GeometricSolution:
    """S_R W_P: only ElbowYaw (upper-arm rotation) moves (eq. 13).

    Raises:
        PrimitiveCannotReachError: if the target is off the circle the wrist
            sweeps round the upper arm, or beyond ElbowYaw's range.
    """
    q = np.array(start, dtype=float)
    points = arm.fk(q)
    axis = arm.rotation(q, "elbow")[:, 0]
    p0 = _off_axis(points.wrist - points.elbow, axis)
    pt = _off_axis(target - points.elbow, axis)
    radius = float(np.linalg.norm(p0))
    reason = "only ElbowYaw moves, so the wrist stays on a circle about the upper arm"
    if radius < 1e-9:
        return _finish(arm, q, target, "S_R W_P", reason + " of radius 0", tol)
    chord = float(np.linalg.norm(target - points.wrist))
    turn = math.acos(min(max((2 * radius**2 - chord**2) / (2 * radius**2), -1.0), 1.0))
    if float(axis @ np.cross(p0, pt)) < 0.0:
        turn = -turn
    q[ELBOW_YAW] += turn
    return _finish(arm, q, target, "S_R W_P", reason, tol)


def _off_axis(v: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Component of ``v`` normal to the unit ``axis``."""
    return v - float(v @ axis) * axis


def solve_wrist_turn(
    arm: ArmModel,
    start: np.ndarray,
    target: np.ndarray,
    palm: np.ndarray | None,
    tol: float,
) -> GeometricSolution:
    """W_R: only WristYaw turns, by the roll that best faces the palm to ``palm``.

    The forearm stays where it is, so the palm meets ``palm`` only as far as
    a roll about the forearm can turn it there.

    Raises:
        InvalidInputError: if no palm direction is given.
        PrimitiveCannotReachError: if the target is not where the wrist is, or
            the turn would leave WristYaw's range.
    """
    if palm is None:
        raise InvalidInputError(
            "W_R turns the wrist in place: give a palm direction", field="palm"
        )
    q = np.array(start, dtype=float)
    q[WRIST_YAW] += roll_error(arm.rotation(q, "wrist"), arm.side.sign, palm)
    low, high = arm.limits.lower[WRIST_YAW], arm.limits.upper[WRIST_YAW]
    if not low <= q[WRIST_YAW] <= high:
        wrist = arm.fk(start).wrist
        raise PrimitiveCannotReachError(
            "W_R",
            target,
            wrist,
            float(np.linalg.norm(wrist - target)),
            f"the roll that turns the palm towards the wanted direction needs "
            f"WristYaw = {q[WRIST_YAW]:.3f} rad, outside "
            f"[{low:.3f}, {high:.3f}] rad",
        )
    return _finish(arm, q, target, "W_R", "W_R holds the wrist in place", tol)
