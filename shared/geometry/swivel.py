"""The elbow swivel angle phi of the torsion-spring model (paper eq. 17).

Zhao et al.'s spring runs along the shoulder-wrist axis n; one end is fixed to
the vertical plane through n, the other to the arm plane (shoulder, elbow,
wrist). We measure phi about n (right-hand rule, n from shoulder to wrist)
from the upward vertical projected onto the plane normal to n, to the elbow's
offset from the axis, in [0, 2 pi):

    phi = 0       elbow straight up (above the shoulder-wrist axis)
    phi = pi      elbow straight down: the natural posture, where the spring
                  energy mu (pi - phi)^2 / 2 is zero.

The wrap-around sits at "elbow straight up", a posture no reach passes
through, so the energy is smooth wherever the arm is used. phi is undefined
for a straight arm (elbow on the axis) or a vertical axis; there the formulas
below return pi and a zero gradient rather than dividing by zero.

With e = elbow - shoulder, w = wrist - shoulder and up = z:
    y = (w_y e_x - w_x e_y) / |w|,   x = e_z - w_z (e.w) / |w|^2,
    phi = atan2(y, x).

Written on plain floats, cheap enough for the IK's inner loop (see
``services.ik.kernel``): ``swivel_angle`` and ``swivel_gradient`` accept any
3-sequences (numpy arrays too); the ``*_and_gradient`` functions the inner
loop calls take float tuples and lists of them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Final

#: Swivel angle of the elbow hanging straight down [rad].
SWIVEL_DOWN: Final = math.pi

_EPS: Final = 1e-12
_TWO_PI: Final = 2.0 * math.pi
#: A point, any 3-sequence (numpy arrays too).
Point = Sequence[float]
#: A point as 3 floats: what the IK's inner loop passes (compiled, no indexing
#: through Python's sequence protocol).
Vec3 = tuple[float, float, float]


def swivel_angle(shoulder: Point, elbow: Point, wrist: Point) -> float:
    """Elbow swivel angle phi in [0, 2 pi) [rad] (pi = elbow straight down).

    Args:
        shoulder: Shoulder position [m], 3 values.
        elbow: Elbow position [m], 3 values.
        wrist: Wrist position [m], 3 values.
    """
    sx, sy, sz = float(shoulder[0]), float(shoulder[1]), float(shoulder[2])
    ex, ey, ez = float(elbow[0]) - sx, float(elbow[1]) - sy, float(elbow[2]) - sz
    wx, wy, wz = float(wrist[0]) - sx, float(wrist[1]) - sy, float(wrist[2]) - sz
    ww = max(wx * wx + wy * wy + wz * wz, _EPS)
    y = (wy * ex - wx * ey) / math.sqrt(ww)
    x = ez - wz * (ex * wx + ey * wy + ez * wz) / ww
    if x * x + y * y < _EPS**2:
        return SWIVEL_DOWN
    return math.atan2(y, x) % _TWO_PI


def swivel_gradient(
    shoulder: Point,
    elbow: Point,
    wrist: Point,
    elbow_columns: Sequence[Point],
    wrist_columns: Sequence[Point],
) -> list[float]:
    """d(phi)/dq [rad/rad], one value per joint, by the chain rule.

    Args:
        shoulder: Shoulder position [m]; it does not move with q.
        elbow: Elbow position [m].
        wrist: Wrist position [m].
        elbow_columns: d(elbow)/dq_k [m/rad], one 3-vector per joint.
        wrist_columns: d(wrist)/dq_k [m/rad], one 3-vector per joint.
    """
    return swivel_and_gradient(
        _vec3(shoulder),
        _vec3(elbow),
        _vec3(wrist),
        [_vec3(c) for c in elbow_columns],
        [_vec3(c) for c in wrist_columns],
    )[1]


def _vec3(v: Point) -> Vec3:
    return (float(v[0]), float(v[1]), float(v[2]))


def swivel_and_gradient(
    shoulder: Vec3,
    elbow: Vec3,
    wrist: Vec3,
    elbow_columns: list[Vec3],
    wrist_columns: list[Vec3],
) -> tuple[float, list[float]]:
    """(phi [rad], d(phi)/dq [rad/rad]) in one pass (they share every term)."""
    sx, sy, sz = shoulder[0], shoulder[1], shoulder[2]
    ex, ey, ez = elbow[0] - sx, elbow[1] - sy, elbow[2] - sz
    wx, wy, wz = wrist[0] - sx, wrist[1] - sy, wrist[2] - sz
    ww = wx * wx + wy * wy + wz * wz
    n = len(wrist_columns)
    if ww < _EPS:
        return SWIVEL_DOWN, [0.0] * n
    nw = math.sqrt(ww)
    ew = ex * wx + ey * wy + ez * wz
    y = (wy * ex - wx * ey) / nw
    x = ez - wz * ew / ww
    r2 = x * x + y * y
    if r2 < _EPS**2:
        return SWIVEL_DOWN, [0.0] * n
    phi = math.atan2(y, x) % _TWO_PI
    # d(phi) = (x dy - y dx) / r2, with dy, dx by e and by w
    k = 2.0 * wz * ew / (ww * ww)
    a, b = x / r2, y / r2
    de0 = a * wy / nw + b * wz * wx / ww
    de1 = -a * wx / nw + b * wz * wy / ww
    de2 = -b * (1.0 - wz * wz / ww)
    dw0 = a * (-ey / nw - y * wx / ww) - b * (-(wz * ex) / ww + k * wx)
    dw1 = a * (ex / nw - y * wy / ww) - b * (-(wz * ey) / ww + k * wy)
    dw2 = a * (-y * wz / ww) - b * (-(ew + wz * ez) / ww + k * wz)
    grad = [0.0] * n
    for j in range(n):
        ce, cw = elbow_columns[j], wrist_columns[j]
        grad[j] = (
            de0 * ce[0] + de1 * ce[1] + de2 * ce[2]
            + dw0 * cw[0] + dw1 * cw[1] + dw2 * cw[2]
        )  # fmt: skip
    return phi, grad


def elbow_offset_and_gradient(
    shoulder: Vec3,
    elbow: Vec3,
    wrist: Vec3,
    elbow_columns: list[Vec3],
    wrist_columns: list[Vec3],
) -> tuple[float, list[float]]:
    """(r^2 [m^2], d(r^2)/dq [m^2/rad]) of the elbow's offset from the arm's line.

    r is the elbow's distance from the shoulder-wrist line: it says how well
    the swivel angle is defined.

    r^2 = |e|^2 - (e.w)^2 / |w|^2 with e, w the elbow and wrist from the
    shoulder; it is zero for a straight arm.

    Args:
        shoulder: Shoulder position [m]; it does not move with q.
        elbow: Elbow position [m].
        wrist: Wrist position [m].
        elbow_columns: d(elbow)/dq_k [m/rad], one 3-vector per joint.
        wrist_columns: d(wrist)/dq_k [m/rad], one 3-vector per joint.
    """
    sx, sy, sz = shoulder[0], shoulder[1], shoulder[2]
    ex, ey, ez = elbow[0] - sx, elbow[1] - sy, elbow[2] - sz
    wx, wy, wz = wrist[0] - sx, wrist[1] - sy, wrist[2] - sz
    ww = wx * wx + wy * wy + wz * wz
    if ww < _EPS:
        return 0.0, [0.0] * len(wrist_columns)
    ew = ex * wx + ey * wy + ez * wz
    r2 = max(ex * ex + ey * ey + ez * ez - ew * ew / ww, 0.0)
    a, b = 2.0 * ew / ww, 2.0 * ew * ew / (ww * ww)
    # d(r^2) = 2 e.de - a (w.de + e.dw) + b w.dw
    g0, g1, g2 = 2.0 * ex - a * wx, 2.0 * ey - a * wy, 2.0 * ez - a * wz
    h0, h1, h2 = b * wx - a * ex, b * wy - a * ey, b * wz - a * ez
    grad = [0.0] * len(wrist_columns)
    for k in range(len(grad)):
        ce, cw = elbow_columns[k], wrist_columns[k]
        grad[k] = (
            g0 * ce[0] + g1 * ce[1] + g2 * ce[2] + h0 * cw[0] + h1 * cw[1] + h2 * cw[2]
        )
    return r2, grad
