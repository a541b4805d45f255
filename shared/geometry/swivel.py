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

With e = elbow - shoulder, w = wrist - shoulder, up = (0, 0, 1):
    y = det[w, up, e] / |w|,   x = up.e - (up.w)(e.w)/|w|^2,   phi = atan2(y, x).
"""

from __future__ import annotations

import math

import numpy as np

from shared.geometry.vectors import cross

#: Swivel angle of the elbow hanging straight down [rad].
SWIVEL_DOWN = math.pi

_UP = np.array([0.0, 0.0, 1.0])
_EPS = 1e-12


def _terms(e: np.ndarray, w: np.ndarray) -> tuple[float, float, float]:
    """(y, x, |w|^2) of the atan2 form above."""
    ww = float(w @ w)
    y = float(np.dot(cross(w, _UP), e)) / math.sqrt(max(ww, _EPS))
    x = float(e[2] - w[2] * float(e @ w) / max(ww, _EPS))
    return y, x, ww


def swivel_angle(shoulder: np.ndarray, elbow: np.ndarray, wrist: np.ndarray) -> float:
    """Elbow swivel angle phi in [0, 2 pi) [rad] (pi = elbow straight down).

    Args:
        shoulder: Shoulder position [m], shape (3,).
        elbow: Elbow position [m], shape (3,).
        wrist: Wrist position [m], shape (3,).
    """
    y, x, _ = _terms(elbow - shoulder, wrist - shoulder)
    if x * x + y * y < _EPS**2:
        return SWIVEL_DOWN
    return math.atan2(y, x) % (2.0 * math.pi)


def swivel_gradient(
    shoulder: np.ndarray,
    elbow: np.ndarray,
    wrist: np.ndarray,
    elbow_jacobian: np.ndarray,
    wrist_jacobian: np.ndarray,
) -> np.ndarray:
    """d(phi)/dq [rad/rad], shape (n,), by the chain rule through elbow and wrist.

    Args:
        shoulder: Shoulder position [m], shape (3,); it does not move.
        elbow: Elbow position [m], shape (3,).
        wrist: Wrist position [m], shape (3,).
        elbow_jacobian: d(elbow)/dq [m/rad], shape (3, n).
        wrist_jacobian: d(wrist)/dq [m/rad], shape (3, n).
    """
    e, w = elbow - shoulder, wrist - shoulder
    y, x, ww = _terms(e, w)
    r2 = x * x + y * y
    if r2 < _EPS**2 or ww < _EPS:
        return np.zeros(elbow_jacobian.shape[1])
    nw = math.sqrt(ww)
    up_w, e_w = float(w[2]), float(e @ w)
    w_x_up = cross(w, _UP)
    dy_de = w_x_up / nw
    dy_dw = cross(_UP, e) / nw - y * w / ww
    dx_de = _UP - up_w * w / ww
    dx_dw = -(e_w * _UP + up_w * e) / ww + 2.0 * up_w * e_w * w / (ww * ww)
    dphi_de = (x * dy_de - y * dx_de) / r2
    dphi_dw = (x * dy_dw - y * dx_dw) / r2
    return dphi_de @ elbow_jacobian + dphi_dw @ wrist_jacobian
