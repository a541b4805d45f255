"""A joint's command over time: straight lines between timed keys."""

from __future__ import annotations

import numpy as np


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
