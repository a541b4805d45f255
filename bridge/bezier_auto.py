"""The curve Choregraphe's runtime plays through a timeline's keys, and its check.

A key written without ``<Tangent>`` elements has BezierAuto tangents
(libqicore-compat ``TangentModel``: ``InterpolationType_BezierAuto`` by
default), which the runtime computes when it loads the timeline
(``TimelinePrivate::rebuildBezierAutoTangents`` and
``updateBezierAutoTangents``) and sends with the keys to
``ALMotion.angleInterpolationBezier``. For a key between two others whose
value lies strictly between theirs, the slope ``beta`` [value per frame] is
the neighbours' (``(right - left) / frames apart``), scaled down so that
neither handle, a third of the way to a neighbour, passes that neighbour's
value (anti-overshoot); at the first and last keys and at a key that is not
between its neighbours (an extremum, or level with one), ``beta`` is 0.
Each handle is a third of the way to the neighbour in time, so between
keys ``i`` and ``i + 1`` the Bezier curve is, in time, the cubic Hermite
curve through the two keys with slopes ``beta_i`` and ``beta_(i+1)``.

That curve is not the frames: it passes through every key but between
them it can be steeper or bend harder than the divided differences of the
keys show (forced level at every key where a joint turns back, it bends
more there). :func:`check_played_curve` therefore checks the curve itself,
exactly: its speed (a quadratic in each segment: largest at an end or its
vertex), its acceleration (linear in each segment: largest at an end) and
its jerk (constant in each segment). Its angles need no check: the handles
stay within the neighbouring keys' values, so the curve stays within the
keys' range. At a key the curve's acceleration may step (the curve is only
once differentiable there); both sides are within the acceleration limit.
"""

from __future__ import annotations

import numpy as np

from bridge.checks import SLACK
from bridge.limits import FrameLimits
from bridge.units import unit
from shared.errors import TrajectoryRefusedError, fixed
from shared.messages import CommandFrames

#: Where a key's handles lie, as a fraction of the way to its neighbour.
ALPHA = 1.0 / 3.0


def auto_slopes(frames: np.ndarray, values: np.ndarray) -> np.ndarray:
    """BezierAuto slope of every key [value per frame], shape (m, n).

    Args:
        frames: Frame numbers of the keys, increasing, shape (m,).
        values: Their values, shape (m, n) (one column per curve).
    """
    beta = np.zeros_like(values)
    if len(values) < 3:
        return beta
    f = frames.astype(float)[:, None]
    left, x, right = values[:-2], values[1:-1], values[2:]
    between = ((x < right) | (x < left)) & ((x > right) | (x > left))
    slope = (right - left) / (f[2:] - f[:-2])
    slope = _clamped(slope, ALPHA * (f[2:] - f[1:-1]) * slope, right - x)
    slope = _clamped(slope, ALPHA * (f[1:-1] - f[:-2]) * slope, x - left)
    beta[1:-1] = np.where(between, slope, 0.0)
    return beta


def _clamped(slope: np.ndarray, height: np.ndarray, room: np.ndarray) -> np.ndarray:
    """``slope`` scaled so that a handle of ``height`` rises no more than ``room``."""
    over = np.abs(height) > np.abs(room)
    safe = np.where(over, height, 1.0)
    return np.where(over, slope * room / safe, slope)


class CurvePeaks:
    """Largest speed, acceleration and jerk of the played curve, per segment.

    Attributes:
        speed: Largest |speed| in each segment [rad/s], shape (m - 1, n).
        acceleration: Largest |acceleration| [rad/s^2], shape (m - 1, n).
        jerk: |jerk| (constant in a segment) [rad/s^3], shape (m - 1, n).
    """

    def __init__(self, times: np.ndarray, values: np.ndarray, fps: float) -> None:
        """The peaks of the curve through keys at ``times`` [s] of ``values`` [rad].

        Args:
            times: Key times, one frame apart or more [s], shape (m,).
            values: Key values [rad], shape (m, n).
            fps: Frames per second of the timeline [Hz].
        """
        frames = np.rint(times * fps)
        beta = auto_slopes(frames, values)
        span = np.diff(frames)[:, None]  # frames per segment
        dt = np.diff(times)[:, None]  # [s]
        d = np.diff(values, axis=0)
        m0, m1 = beta[:-1] * span, beta[1:] * span  # slopes per unit of s
        # dq/ds = a s^2 + b s + c on s in [0, 1]
        a, b, c = -6 * d + 3 * m0 + 3 * m1, 6 * d - 4 * m0 - 2 * m1, m0
        vertex = np.clip(-b / np.where(a == 0.0, 1.0, 2 * a), 0.0, 1.0)
        at_vertex = np.where(a == 0.0, 0.0, (a * vertex + b) * vertex + c)
        ds = np.maximum.reduce([np.abs(c), np.abs(a + b + c), np.abs(at_vertex)])
        dds = np.maximum(np.abs(b), np.abs(2 * a + b))
        self.speed = ds / dt
        self.acceleration = dds / dt**2
        self.jerk = np.abs(2 * a) / dt**3


def check_played_curve(played: CommandFrames, limits: FrameLimits) -> None:
    """Refuse keys whose BezierAuto curve breaks a speed, acceleration or jerk limit.

    Args:
        played: The keys as command frames (``bridge.timeline_keys.
            behavior_frames``): the start at 0 s, then one key per frame [s, rad].
        limits: The joints' limits.

    Raises:
        TrajectoryRefusedError: naming the joint, the quantity and the keys
            (frames) between which the curve is over its limit.
    """
    times = np.concatenate([[0.0], played.times])
    values = np.vstack([np.asarray(played.start)[None, :], played.positions])
    peaks = CurvePeaks(times, values, played.rate)
    for order, quantity, value, bound in (
        (1, "velocity", peaks.speed, limits.velocity),
        (2, "acceleration", peaks.acceleration, limits.acceleration),
        (3, "jerk", peaks.jerk, limits.jerk),
    ):
        over = np.argwhere(value > bound * (1.0 + SLACK))
        if len(over):
            k, j = (int(i) for i in over[0])
            per = unit(limits.names[j], order)
            raise TrajectoryRefusedError(
                limits.names[j],
                quantity,
                value[k, j],
                bound[j],
                frame=k,
                time=times[k],
                detail=(
                    f"{quantity} {fixed(value[k, j], 2)}{per} between frames {k} "
                    f"and {k + 1} (t = {times[k]:.3f} to {times[k + 1]:.3f} s) "
                    "on the curve Choregraphe plays through the keys (BezierAuto) "
                    f"exceeds its limit {bound[j]:.2f}{per}"
                ),
            )
