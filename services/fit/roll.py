"""The wrist's remaining orientation change W_R: roll still to make.

The paper gives the wrist's orientation attribute relative to the node
before (Section II.A), so W_R is a roll of the palm about the forearm
measured in the arm's own frame: the angle, about the forearm axis f, from
-n (n = u x f the arm plane's normal, u the upper arm) to the wrist frame's
y axis (the palm normal of a right hand; NAO's wrist frame and the
demonstrations' share this convention).

The roll wanted at the goal needs the arm's frame there, which a decision
made on the way does not know: it is predicted by turning the arm, with the
elbow at its final flexion in its current plane, by the smallest rotation
about the shoulder that puts the wrist on the goal (the rotation whose
angle is S_R). W_R is the difference of the goal's roll in that predicted
frame and the current roll, wrapped to [0, pi]. The same computation serves
the demonstrations (goal: the trial's last wrist frame) and the planner
(goal: the wanted palm direction), so the two see one variable. At the goal
it is 0; once only the elbow moves in its final plane it is exact.

``roll_to_go`` works on many samples (numpy), ``roll_to_go_at`` on one
(plain floats, the decision's fast path); the tests check they agree.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from services.fit.variables import flexion_for_distance

_EPS = 1e-12


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), _EPS)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", a, b)


def _roll(axis: np.ndarray, fore: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Angle about ``fore`` from -``normal`` to ``axis`` [rad], shape (n,)."""
    away = -normal
    return np.arctan2(_dot(axis, np.cross(fore, away)), _dot(axis, away))


def _rotate(
    x: np.ndarray, k: np.ndarray, cos: np.ndarray, sin: np.ndarray
) -> np.ndarray:
    """Rotate rows of ``x`` about unit axes ``k`` (Rodrigues)."""
    return (
        x * cos[:, None]
        + np.cross(k, x) * sin[:, None]
        + k * (_dot(k, x) * (1.0 - cos))[:, None]
    )


def roll_to_go(
    shoulder: np.ndarray,
    elbow: np.ndarray,
    wrist: np.ndarray,
    axis: np.ndarray,
    goal: np.ndarray,
    goal_axis: np.ndarray,
    upper: float,
    forearm: float,
) -> np.ndarray:
    """W_R of n arm states [rad], shape (n,), in [0, pi].

    Args:
        shoulder: Shoulder positions [m], shape (n, 3).
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        axis: The wrist frame's y axis at each state (unit), shape (n, 3).
        goal: Wrist goal [m], shape (3,).
        goal_axis: The wrist frame's y axis wanted at the goal, shape (3,).
        upper: Upper arm length L_u [m].
        forearm: Forearm length L_f [m].
    """
    u = _unit(elbow - shoulder)
    f = _unit(wrist - elbow)
    to_goal = np.broadcast_to(goal, shoulder.shape) - shoulder
    bend = f - _dot(f, u)[:, None] * u
    toward = to_goal - _dot(to_goal, u)[:, None] * u
    straight = np.linalg.norm(bend, axis=1) < 1e-9
    bend[straight] = toward[straight]
    bend = _unit(bend)
    normal = _unit(np.cross(u, bend))
    final = flexion_for_distance(upper, forearm, np.linalg.norm(to_goal, axis=1))
    fore = np.cos(final)[:, None] * u + np.sin(final)[:, None] * bend
    would = upper * u + forearm * fore
    turn = np.cross(would, to_goal)
    sin = np.linalg.norm(turn, axis=1)
    cos = _dot(would, to_goal)
    scale = np.maximum(np.hypot(sin, cos), _EPS)
    k = _unit(turn)
    fore_end = _rotate(fore, k, cos / scale, sin / scale)
    normal_end = _rotate(normal, k, cos / scale, sin / scale)
    wanted = np.broadcast_to(goal_axis, shoulder.shape)
    left = _roll(wanted, fore_end, normal_end) - _roll(axis, f, normal)
    return np.abs(np.angle(np.exp(1j * left)))


def roll_to_go_at(
    shoulder: Sequence[float],
    elbow: Sequence[float],
    wrist: Sequence[float],
    axis: Sequence[float],
    goal: Sequence[float],
    goal_axis: Sequence[float],
    upper: float,
    forearm: float,
) -> float:
    """W_R of one arm state [rad] (plain floats; see :func:`roll_to_go`).

    The same steps as :func:`roll_to_go`, written out on floats: it runs once
    per path point when a palm direction is wanted.
    """
    sx, sy, sz = shoulder[0], shoulder[1], shoulder[2]
    ux, uy, uz = elbow[0] - sx, elbow[1] - sy, elbow[2] - sz
    n = math.sqrt(ux * ux + uy * uy + uz * uz) or _EPS
    ux, uy, uz = ux / n, uy / n, uz / n
    fx, fy, fz = wrist[0] - elbow[0], wrist[1] - elbow[1], wrist[2] - elbow[2]
    n = math.sqrt(fx * fx + fy * fy + fz * fz) or _EPS
    fx, fy, fz = fx / n, fy / n, fz / n
    cx, cy, cz = goal[0] - sx, goal[1] - sy, goal[2] - sz
    along = fx * ux + fy * uy + fz * uz
    bx, by, bz = fx - along * ux, fy - along * uy, fz - along * uz
    if bx * bx + by * by + bz * bz < 1e-18:
        along = cx * ux + cy * uy + cz * uz
        bx, by, bz = cx - along * ux, cy - along * uy, cz - along * uz
    n = math.sqrt(bx * bx + by * by + bz * bz) or _EPS
    bx, by, bz = bx / n, by / n, bz / n
    # the arm plane's normal u x b (unit: u, b orthonormal)
    nx, ny, nz = uy * bz - uz * by, uz * bx - ux * bz, ux * by - uy * bx
    distance2 = cx * cx + cy * cy + cz * cz
    cos_b = (distance2 - upper * upper - forearm * forearm) / (2.0 * upper * forearm)
    final = math.acos(min(max(cos_b, -1.0), 1.0))
    cf, sf = math.cos(final), math.sin(final)
    ex, ey, ez = ux * cf + bx * sf, uy * cf + by * sf, uz * cf + bz * sf
    wx = upper * ux + forearm * ex
    wy = upper * uy + forearm * ey
    wz = upper * uz + forearm * ez
    kx, ky, kz = wy * cz - wz * cy, wz * cx - wx * cz, wx * cy - wy * cx
    sin = math.sqrt(kx * kx + ky * ky + kz * kz)
    cos = wx * cx + wy * cy + wz * cz
    scale = math.hypot(sin, cos) or _EPS
    cos, sin = cos / scale, sin / scale
    n = sin * scale or _EPS
    kx, ky, kz = kx / n, ky / n, kz / n
    # rotate the final forearm e and the normal n about k (Rodrigues)
    kd, ke = kx * ex + ky * ey + kz * ez, kx * nx + ky * ny + kz * nz
    gx = ex * cos + (ky * ez - kz * ey) * sin + kx * kd * (1.0 - cos)
    gy = ey * cos + (kz * ex - kx * ez) * sin + ky * kd * (1.0 - cos)
    gz = ez * cos + (kx * ey - ky * ex) * sin + kz * kd * (1.0 - cos)
    mx = nx * cos + (ky * nz - kz * ny) * sin + kx * ke * (1.0 - cos)
    my = ny * cos + (kz * nx - kx * nz) * sin + ky * ke * (1.0 - cos)
    mz = nz * cos + (kx * ny - ky * nx) * sin + kz * ke * (1.0 - cos)
    # roll = atan2(axis . (f x a), axis . a) with a = -normal
    qx, qy, qz = goal_axis[0], goal_axis[1], goal_axis[2]
    wanted = math.atan2(
        -(
            qx * (gy * mz - gz * my)
            + qy * (gz * mx - gx * mz)
            + qz * (gx * my - gy * mx)
        ),
        -(qx * mx + qy * my + qz * mz),
    )
    ax, ay, az = axis[0], axis[1], axis[2]
    now = math.atan2(
        -(
            ax * (fy * nz - fz * ny)
            + ay * (fz * nx - fx * nz)
            + az * (fx * ny - fy * nx)
        ),
        -(ax * nx + ay * ny + az * nz),
    )
    return abs(math.remainder(wanted - now, 2.0 * math.pi))
