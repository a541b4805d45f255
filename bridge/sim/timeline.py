"""A joint's command over time: straight lines, or a smooth curve, between keys."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]


class KeyTimeline:
    """Setpoint of one joint, linear between keys, held after the last one.

    Attributes:
        start_time: When the command took effect [s, sim clock].
        end_time: When its last key is reached [s, sim clock].
    """

    def __init__(
        self,
        start_time: float,
        start_value: float,
        times: list[float],
        values: list[float],
    ) -> None:
        """Build from the value at reception and the keys.

        Args:
            start_time: When the command took effect [s, sim clock].
            start_value: Setpoint at reception [rad] (stiffness: 0..1).
            times: Key times from reception [s], increasing, first above 0.
            values: Key values, same length as ``times``.
        """
        self.start_time = start_time
        self._times = np.concatenate([[0.0], times])
        self._values = np.concatenate([[start_value], values])
        self.end_time = start_time + float(self._times[-1])

    @property
    def final(self) -> float:
        """Value of the last key."""
        return float(self._values[-1])

    def at(self, t: float) -> float:
        """The setpoint at sim time ``t`` [s]."""
        return float(np.interp(t - self.start_time, self._times, self._values))


class KeyCurve(KeyTimeline):
    """Setpoint of one joint on the smooth curve through its keys.

    The curve is the clamped cubic spline through the value at reception and
    the keys: it goes through every key, its speed and acceleration are
    continuous (acceleration linear and jerk constant between keys), and it
    is at rest (speed 0) at reception and at the last key, as the robot is
    before and after a trajectory (the positions' own curve of
    ``bridge.velocity_agreement``). Straight lines stepped the speed at
    every key: at a 5 ms cycle the logged states of the demo, whose frames
    passed every check, showed 2.7 times the acceleration limit and 27
    times the jerk limit. On this curve the states' finite differences, at
    any cycle, are never above the curve's own speed, acceleration and jerk
    (a k-th divided difference of a curve is a weighted mean of its k-th
    derivative), which for frames that pass the bridge's checks are near
    the frames' own differences (the demo's 0.35 of the limits; a fastest
    plan at the bridge's limits up to 0.75 at 25 fps, 0.96 of the jerk limit at
    100 fps). No curve through keys is bound by the keys' differences alone
    (keys that zigzag need twice their second difference in acceleration on
    any curve through them), so that is measured, not guaranteed. It is
    held in the joint's range: the cubic rings a little past keys that hold
    still before and after a move (a hand resting open or shut on its
    bound, by 4e-4 in the demo), and the cut there shows as jerk at a fine
    cycle (the demo's hand: 2.2 times its limit at 5 ms, 0.3 at 20 ms).
    """

    def __init__(
        self,
        start_time: float,
        start_value: float,
        times: list[float],
        values: list[float],
        within: tuple[float, float],
    ) -> None:
        """Build from the value at reception and the keys.

        Args:
            start_time: When the command took effect [s, sim clock].
            start_value: Setpoint at reception [rad].
            times: Key times from reception [s], increasing, first above 0.
            values: Key values [rad], same length as ``times``.
            within: The joint's range (lower, upper) [rad].
        """
        super().__init__(start_time, start_value, times, values)
        self._curve = CubicSpline(self._times, self._values, bc_type="clamped")
        self._lower, self._upper = within

    def at(self, t: float) -> float:
        """The setpoint at sim time ``t`` [s]: at rest before and after."""
        s = min(max(t - self.start_time, 0.0), float(self._times[-1]))
        return min(max(float(self._curve(s)), self._lower), self._upper)
