"""The five motion variables (paper Section III.A), at one arm state and a goal.

Each variable is what an attribute of the arm still has to change to reach
the goal, normalised by the arm's size (the paper: "the arm size of robot
NAO is involved in the calculation"), so that it is >= 0 and 0 once done:

    S_R  the shoulder's remaining rotation [rad]: the angle, seen from the
         shoulder, between the goal and where the wrist would be if the
         elbow already had its final flexion (same arm plane). It is 0 when
         only the elbow is left to move.
    E_P  the elbow's remaining position change: | |elbow - goal| - L_f | / L.
         0 when the forearm can reach the goal by turning about the elbow
         (the paper: "the difference between the distance from the elbow to
         the target and the length of the lower arm").
    E_R  the elbow's remaining orientation change [rad]: |beta_goal - beta|,
         beta the angle between upper arm and forearm, beta_goal the one that
         puts the wrist at the goal's distance from the shoulder (arm
         triangle, eq. 11).
    W_P  the wrist's remaining position change: | |goal - shoulder| -
         |wrist - shoulder| | / L (the paper: "the difference between the
         distance from the shoulder to the target and the distance from the
         shoulder to the wrist").
    W_R  the wrist's remaining orientation change [rad]: the roll of the palm
         about the forearm still to make (``roll``, given to these functions);
         0, and unobserved by the decision, without a wanted orientation.

L = L_u + L_f, the arm's length. Two implementations: ``motion_variables``
(numpy, many samples, for fitting) and ``variables_at`` (plain floats, one
state, for the per-point decision); the tests check that they agree.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np

# The variables in the network's order (the arm's serial chain), defined with
# the model message.
from shared.messages.motion_model import VARIABLES as VARIABLES

S_R, E_P, E_R, W_P, W_R = range(5)

_EPS: Final = 1e-12
#: A point [m] as 3 floats.
Vec3 = tuple[float, float, float]


def flexion_for_distance(
    upper: float, forearm: float, distance: np.ndarray
) -> np.ndarray:
    """Angle between upper arm and forearm [rad] for a shoulder-wrist distance [m]."""
    cos = (distance**2 - upper**2 - forearm**2) / (2.0 * upper * forearm)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle between rows of ``a`` and ``b`` [rad], shape (n,)."""
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    return np.arctan2(cross, np.einsum("ij,ij->i", a, b))


def motion_variables(
    shoulder: np.ndarray,
    elbow: np.ndarray,
    wrist: np.ndarray,
    goal: np.ndarray,
    upper: float,
    forearm: float,
    roll: np.ndarray | None = None,
) -> np.ndarray:
    """The five variables of n arm states, shape (n, 5), columns ``VARIABLES``.

    Args:
        shoulder: Shoulder positions [m], shape (n, 3).
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        goal: Wrist goal [m], shape (n, 3) or (3,).
        upper: Upper arm length L_u [m].
        forearm: Forearm length L_f [m].
        roll: Remaining wrist roll [rad], shape (n,), or ``None`` when no
            palm direction is wanted (W_R is then 0).
    """
    length = upper + forearm
    goal = np.broadcast_to(goal, shoulder.shape)
    to_goal = goal - shoulder
    distance = np.linalg.norm(to_goal, axis=1)
    arm = elbow - shoulder
    fore = wrist - elbow
    out = np.empty((len(shoulder), 5))
    out[:, W_P] = np.abs(distance - np.linalg.norm(wrist - shoulder, axis=1)) / length
    out[:, E_P] = np.abs(np.linalg.norm(goal - elbow, axis=1) - forearm) / length
    final = flexion_for_distance(upper, forearm, distance)
    out[:, E_R] = np.abs(final - _angle(arm, fore))
    u = arm / np.maximum(np.linalg.norm(arm, axis=1, keepdims=True), _EPS)
    bend = fore - np.einsum("ij,ij->i", fore, u)[:, None] * u
    toward = to_goal - np.einsum("ij,ij->i", to_goal, u)[:, None] * u
    straight = np.linalg.norm(bend, axis=1) < 1e-9
    bend[straight] = toward[straight]
    bend /= np.maximum(np.linalg.norm(bend, axis=1, keepdims=True), _EPS)
    would = upper * u + forearm * (
        np.cos(final)[:, None] * u + np.sin(final)[:, None] * bend
    )
    out[:, S_R] = _angle(would, to_goal)
    out[:, W_R] = 0.0 if roll is None else np.abs(roll)
    return out


def variables_at(
    shoulder: Vec3,
    elbow: Vec3,
    wrist: Vec3,
    goal: Vec3,
    upper: float,
    forearm: float,
    roll: float = 0.0,
) -> tuple[float, float, float, float, float]:
    """The five variables of one arm state, with plain floats (fast path).

    Same definitions as :func:`motion_variables`; positions [m] as float tuples,
    ``roll`` the remaining wrist roll [rad] (0 without a palm direction).

    Returns:
        (S_R [rad], E_P, E_R [rad], W_P, W_R [rad]).
    """
    sx, sy, sz = shoulder
    ax, ay, az = elbow[0] - sx, elbow[1] - sy, elbow[2] - sz
    bx, by, bz = wrist[0] - elbow[0], wrist[1] - elbow[1], wrist[2] - elbow[2]
    cx, cy, cz = goal[0] - sx, goal[1] - sy, goal[2] - sz
    length = upper + forearm
    distance = math.sqrt(cx * cx + cy * cy + cz * cz)
    wx, wy, wz = ax + bx, ay + by, az + bz
    w_p = abs(distance - math.sqrt(wx * wx + wy * wy + wz * wz)) / length
    gx, gy, gz = goal[0] - elbow[0], goal[1] - elbow[1], goal[2] - elbow[2]
    e_p = abs(math.sqrt(gx * gx + gy * gy + gz * gz) - forearm) / length
    cos = (distance * distance - upper * upper - forearm * forearm) / (
        2.0 * upper * forearm
    )
    final = math.acos(min(max(cos, -1.0), 1.0))
    na = math.sqrt(ax * ax + ay * ay + az * az) or _EPS
    ux, uy, uz = ax / na, ay / na, az / na
    ab = bx * ux + by * uy + bz * uz
    px, py, pz = bx - ab * ux, by - ab * uy, bz - ab * uz
    along = math.sqrt(px * px + py * py + pz * pz)
    e_r = abs(final - math.atan2(along, ab))
    if along < 1e-9:
        ac = cx * ux + cy * uy + cz * uz
        px, py, pz = cx - ac * ux, cy - ac * uy, cz - ac * uz
        along = math.sqrt(px * px + py * py + pz * pz) or _EPS
    cf, sf = forearm * math.cos(final), forearm * math.sin(final) / along
    vx = upper * ux + cf * ux + sf * px
    vy = upper * uy + cf * uy + sf * py
    vz = upper * uz + cf * uz + sf * pz
    kx, ky, kz = vy * cz - vz * cy, vz * cx - vx * cz, vx * cy - vy * cx
    s_r = math.atan2(
        math.sqrt(kx * kx + ky * ky + kz * kz), vx * cx + vy * cy + vz * cz
    )
    return (s_r, e_p, e_r, w_p, abs(roll))
