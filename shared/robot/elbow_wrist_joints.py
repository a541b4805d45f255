"""The four arm joints that put NAO's elbow and wrist on two points, in closed form.

NAO's arm (the robot file, ``nao_arms.urdf``): ShoulderPitch turns about y
and ShoulderRoll about z at the shoulder S; the elbow E lies at the offset
u = (0.105, -+0.015, 0) [m] in the ShoulderRoll frame; ElbowYaw turns
about that frame's x axis and ElbowRoll about z at E; the wrist W lies at
(L_f, 0, 0) in the ElbowRoll frame. So, with R_a(t) a rotation by t about
axis a,

    E - S = R_y(p) R_z(r) u
    g := (R_y(p) R_z(r))^T (W - E) = R_x(y) R_z(e) (L_f, 0, 0)
       = L_f (cos e, sin e cos y, sin e sin y)

The first line's y row is u_x sin r + u_y cos r = (E - S)_y, which gives r
(two roots a half turn apart), and then its x and z rows give p. The
second gives e = +-acos(g_x / L_f) and y from the signs of g_y, g_z over
sin e. Within NAO's ranges only one root of each is left (ShoulderRoll
spans 94 deg, ElbowRoll keeps one sign), so where the points are exactly
at NAO's segment lengths and the posture within its ranges, it is the
one posture that puts the arm on them.

Retargeted human postures are such points (``shared.demos.retarget``):
:func:`shared.demos.posture_from_points.joints_from_points` takes this
answer where it exists and is checked by the forward kinematics, and
solves by bounded least squares only where the human posture is outside
NAO's ranges. Least squares took about 2 ms a posture; this 0.1 to 0.2 ms.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from shared.robot.arm_model import ArmModel

#: Farthest the posture found may put the elbow or the wrist from its point
#: [m]: anything above rounding means the points are not at NAO's lengths.
EXACT = 1e-9


def elbow_wrist_joints(
    arm: ArmModel, elbow: np.ndarray, wrist: np.ndarray, guess: np.ndarray
) -> np.ndarray | None:
    """ShoulderPitch, ShoulderRoll, ElbowYaw, ElbowRoll [rad], shape (4,).

    The posture within the arm's ranges that puts its elbow on ``elbow``
    and its wrist on ``wrist`` (torso frame [m], each shape (3,)) within
    :data:`EXACT`; the one nearest ``guess`` [rad], shape (5,) or (4,), if
    there were several. ``None`` if there is none: the points are not at
    the arm's segment lengths, or the posture is out of its ranges.
    """
    lower, upper = arm.limits.lower[:4], arm.limits.upper[:4]
    found = [
        q
        for q in _candidates(arm, elbow, wrist)
        if np.all((lower <= q) & (q <= upper)) and _puts(arm, q, elbow, wrist)
    ]
    if not found:
        return None
    near = np.asarray(guess, dtype=float)[:4]
    return min(found, key=lambda q: float(np.abs(q - near).max()))


def _candidates(
    arm: ArmModel, elbow: np.ndarray, wrist: np.ndarray
) -> Iterator[np.ndarray]:
    """Every root of the two equations (module docstring), ranges unchecked."""
    u = arm.elbow_offset
    lf = arm.forearm_length
    d = np.asarray(elbow, dtype=float) - arm.shoulder_position
    reach = math.hypot(u[0], u[1])
    turn = math.asin(_clip(d[1] / reach))
    lean = math.atan2(u[1], u[0])
    for r in (turn - lean, math.pi - turn - lean):
        roll = math.remainder(r, math.tau)
        along = u[0] * math.cos(roll) - u[1] * math.sin(roll)  # (R_z(r) u)_x
        if abs(along) < 1e-12:
            continue  # the elbow straight above or below: no pitch to find
        sign = math.copysign(1.0, along)
        pitch = math.atan2(-d[2] * sign, d[0] * sign)
        g = _upper_arm_frame(pitch, roll).T @ (np.asarray(wrist, dtype=float) - elbow)
        bend = math.acos(_clip(g[0] / lf))
        for e in (bend, -bend):
            if math.sin(e) == 0.0:
                continue  # a straight arm: ElbowYaw moves nothing
            s = math.copysign(1.0, math.sin(e))
            yaw = math.atan2(s * g[2], s * g[1])
            yield np.array([pitch, roll, yaw, e])


def _upper_arm_frame(pitch: float, roll: float) -> np.ndarray:
    """R_y(pitch) R_z(roll), shape (3, 3)."""
    cp, sp, cr, sr = math.cos(pitch), math.sin(pitch), math.cos(roll), math.sin(roll)
    return np.array([[cp * cr, -cp * sr, sp], [sr, cr, 0.0], [-sp * cr, sp * sr, cp]])


def _puts(arm: ArmModel, q: np.ndarray, elbow: np.ndarray, wrist: np.ndarray) -> bool:
    """Whether posture ``q`` (4,) puts elbow and wrist within ``EXACT`` of theirs."""
    points = arm.fk(np.concatenate((q, [0.0])))
    return bool(
        np.abs(points.elbow - elbow).max() <= EXACT
        and np.abs(points.wrist - wrist).max() <= EXACT
    )


def _clip(x: float) -> float:
    """``x`` within [-1, 1] (rounding may put a cosine a hair outside)."""
    return min(max(float(x), -1.0), 1.0)
