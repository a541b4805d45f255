"""The curve Choregraphe's runtime plays through a timeline's keys, and its check.

The runtime sends a timeline's keys with their tangents' handles to
``ALMotion.angleInterpolationBezier`` (``bridge.key_tangents``): between
two keys a cubic Bezier curve through the key, its right handle, the next
key's left handle and the next key. With the handles a third of the way
in time (armplan's tangents, and the runtime's own BezierAuto ones), the
curve's time runs evenly and its value is a cubic in time: the Hermite
curve whose slopes at the keys are the handles' (``3 * ordinate`` per
segment).

:func:`check_played_curve` checks that curve itself, exactly, segment by
segment: its angle (largest and smallest at an end or where its speed is
0), its speed (a quadratic: largest at an end or its vertex), its
acceleration (linear: largest at an end) and its jerk (constant). At a key
the curve's acceleration may step (it is only once differentiable there);
both sides are within the acceleration limit.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from bridge.checks import SLACK
from bridge.float32 import degrees_as_radians, frame_times, held
from bridge.key_tangents import ALPHA, key_spans
from bridge.limits import FrameLimits
from bridge.timeline_keys import TimelineKeys, is_hand
from bridge.units import unit, value_name
from shared.errors import InvalidInputError, TrajectoryRefusedError, fixed

#: How far a handle's abscissa may be from a third of the way to its
#: neighbour [frames] (written to 1e-9 frame; the runtime holds 32 bits).
ABSCISSA_TOLERANCE = 1e-6


class PlayedCurve(NamedTuple):
    """A timeline's curves as the runtime plays them, all keyed alike.

    Attributes:
        names: Actuators, shape (n,).
        times: Key times from the timeline's start [s], shape (m,).
        values: Key values [rad; fraction for a hand], shape (m, n).
        left: Height of each key's left handle above the key [rad;
            fraction], shape (m, n).
        right: Height of each key's right handle, likewise.
    """

    names: list[str]
    times: np.ndarray
    values: np.ndarray
    left: np.ndarray
    right: np.ndarray


def played_curve(keys: TimelineKeys) -> PlayedCurve:
    """The curve the runtime plays through ``keys`` and their handles.

    Times, values and handle heights in 32-bit floats, as the runtime
    computes them (``float(frame - start_frame) / fps``, ``value * TO_RAD``,
    ``ordinate * TO_RAD``; a hand's unscaled).

    Raises:
        InvalidInputError: the curves are not keyed on the same frames, or a
            handle is not a third of the way to its neighbour (such a curve
            is not a cubic in time, and not checked here).
    """
    numbers = keys.frames[0]
    if any(not np.array_equal(f, numbers) for f in keys.frames):
        raise InvalidInputError(
            "the timeline's curves are not keyed on the same frames", field="keys"
        )
    before, after = key_spans(numbers)
    columns = [
        _heights(keys, name, -ALPHA * before, ALPHA * after) for name in keys.names
    ]
    values = [
        keys.values[j] if is_hand(name) else degrees_as_radians(keys.values[j])
        for j, name in enumerate(keys.names)
    ]
    return PlayedCurve(
        names=list(keys.names),
        times=frame_times(numbers - keys.start_frame, keys.fps),
        values=held(np.column_stack(values)),
        left=np.column_stack([c[0] for c in columns]),
        right=np.column_stack([c[1] for c in columns]),
    )


def _heights(
    keys: TimelineKeys, name: str, left_x: np.ndarray, right_x: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``name``'s left and right handle heights [rad; fraction], each (m,)."""
    heights = []
    for handle, expected, side in zip(
        keys.handles(name), (left_x, right_x), ("left", "right"), strict=True
    ):
        off = np.flatnonzero(np.abs(handle[:, 0] - expected) > ABSCISSA_TOLERANCE)
        if len(off):
            k = int(off[0])
            raise InvalidInputError(
                f"{name}'s key at frame {int(keys.frames[0][k])} has its {side} "
                f"handle at {handle[k, 0]:g} frames, not a third of the way to "
                f"its neighbour ({expected[k]:g}): armplan checks only such curves",
                field="Tangent",
            )
        y = handle[:, 1]
        heights.append(held(y) if is_hand(name) else degrees_as_radians(y))
    return heights[0], heights[1]


class CurvePeaks:
    """Extremes of the played curve in each segment between keys.

    Attributes:
        lowest: Smallest value in each segment [rad], shape (m - 1, n).
        highest: Largest value [rad], shape (m - 1, n).
        speed: Largest |speed| [rad/s], shape (m - 1, n).
        acceleration: Largest |acceleration| [rad/s^2], shape (m - 1, n).
        jerk: |jerk| (constant in a segment) [rad/s^3], shape (m - 1, n).
    """

    def __init__(self, curve: PlayedCurve) -> None:
        """The extremes of ``curve``, whose keys are one frame apart or more."""
        dt = np.diff(curve.times)[:, None]  # [s]
        q0 = curve.values[:-1]
        d = np.diff(curve.values, axis=0)
        m0, m1 = 3.0 * curve.right[:-1], -3.0 * curve.left[1:]  # per unit of s
        # dq/ds = a s^2 + b s + c on s in [0, 1]
        a, b, c = -6 * d + 3 * m0 + 3 * m1, 6 * d - 4 * m0 - 2 * m1, m0
        vertex = np.clip(-b / np.where(a == 0.0, 1.0, 2 * a), 0.0, 1.0)
        at_vertex = np.where(a == 0.0, 0.0, (a * vertex + b) * vertex + c)
        ds = np.maximum.reduce([np.abs(c), np.abs(a + b + c), np.abs(at_vertex)])
        dds = np.maximum(np.abs(b), np.abs(2 * a + b))
        at = [q0 + s * (c + s * (b / 2 + s * a / 3)) for s in _stops(a, b, c)]
        self.lowest = np.minimum.reduce(at)
        self.highest = np.maximum.reduce(at)
        self.speed = ds / dt
        self.acceleration = dds / dt**2
        self.jerk = np.abs(2 * a) / dt**3


def _stops(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> list[np.ndarray]:
    """Where ``a s^2 + b s + c`` is 0 in [0, 1], and the ends: 4 arrays of s.

    A root outside [0, 1], or none, is replaced by an end.
    """
    disc = b * b - 4 * a * c
    root = np.sqrt(np.maximum(disc, 0.0))
    quadratic = (a != 0.0) & (disc >= 0.0)
    safe_a = np.where(a != 0.0, 2 * a, 1.0)
    linear = np.where(b != 0.0, -c / np.where(b != 0.0, b, 1.0), 0.0)
    first = np.where(quadratic, (-b + root) / safe_a, np.where(a == 0.0, linear, 0.0))
    second = np.where(quadratic, (-b - root) / safe_a, 0.0)
    ends = np.zeros_like(a), np.ones_like(a)
    return [*ends, np.clip(first, 0.0, 1.0), np.clip(second, 0.0, 1.0)]


def check_played_curve(curve: PlayedCurve, limits: FrameLimits) -> None:
    """Refuse a curve that leaves a joint's range or breaks a motion limit.

    Args:
        curve: The curve a behavior's timeline plays (:func:`played_curve`),
            the start at 0 s.
        limits: The joints' limits, for the curve's actuators in order.

    Raises:
        InvalidInputError: the curve moves other joints than the limits'.
        TrajectoryRefusedError: naming the joint, the quantity and the keys
            (frames) between which the curve is over its limit.
    """
    if tuple(curve.names) != tuple(limits.names):
        raise InvalidInputError(
            f"the curve moves {curve.names}, expected the joints {list(limits.names)}",
            field="joint_names",
        )
    peaks = CurvePeaks(curve)
    _check_range(curve, peaks, limits)
    for order, quantity, value, bound in (
        (1, "velocity", peaks.speed, limits.velocity),
        (2, "acceleration", peaks.acceleration, limits.acceleration),
        (3, "jerk", peaks.jerk, limits.jerk),
    ):
        over = np.argwhere(value > bound * (1.0 + SLACK))
        if len(over):
            k, j = (int(i) for i in over[0])
            per = unit(limits.names[j], order)
            _refuse(
                curve,
                k,
                limits.names[j],
                (quantity, order),
                (value[k, j], bound[j]),
                f"exceeds its limit {bound[j]:.2f}{per}",
            )


def _check_range(curve: PlayedCurve, peaks: CurvePeaks, limits: FrameLimits) -> None:
    """Refuse the first segment that leaves its joint's range."""
    slack = SLACK * np.maximum(1.0, np.abs(limits.upper - limits.lower))
    low = peaks.lowest < limits.lower - slack
    high = peaks.highest > limits.upper + slack
    over = np.argwhere(low | high)
    if len(over):
        k, j = (int(i) for i in over[0])
        value, bound = (
            (peaks.lowest[k, j], limits.lower[j])
            if low[k, j]
            else (peaks.highest[k, j], limits.upper[j])
        )
        name = limits.names[j]
        span = f"[{limits.lower[j]:.4f}, {limits.upper[j]:.4f}]{unit(name)}"
        breaks = f"is outside its range {span}"
        _refuse(curve, k, name, ("position", 0), (value, bound), breaks)


def _refuse(
    curve: PlayedCurve,
    k: int,
    name: str,
    quantity: tuple[str, int],
    value: tuple[float, float],
    breaks: str,
) -> None:
    """Raise the refusal of segment ``k`` (between keys ``k`` and ``k + 1``).

    Args:
        curve: The curve.
        k: The segment.
        name: The joint.
        quantity: What is refused and its order (0 for the angle, 1 speed...).
        value: The value found and the bound it crosses.
        breaks: How it breaks the bound, the message's end.
    """
    (what, order), (found, bound) = quantity, value
    per = unit(name, order)
    shown = value_name(name) if order == 0 else what
    t0, t1 = curve.times[k], curve.times[k + 1]
    raise TrajectoryRefusedError(
        name,
        what,
        found,
        bound,
        frame=k,
        time=t0,
        detail=(
            f"{shown} {fixed(found, 4 if order == 0 else 2)}{per} between frames {k} "
            f"and {k + 1} (t = {t0:.3f} to {t1:.3f} s) on the curve Choregraphe "
            f"plays through the keys {breaks}"
        ),
    )
