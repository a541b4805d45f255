"""The human bell: Ruckig's profile under the bell limits is minimum-jerk-like."""

from __future__ import annotations

import numpy as np
import pytest

from services.timing.human_pace import PEAK_SPEED, bell_limits, minimum_jerk_speed
from services.timing.parameter_limits import motion_time
from services.timing.scalar_profile import plan_rest_to_rest


@pytest.mark.parametrize(("length", "duration"), [(1.0, 1.0), (0.3, 0.55), (2.5, 1.01)])
def test_the_bell_takes_exactly_its_duration(length: float, duration: float) -> None:
    """The time-optimal motion under bell_limits(L, T) takes T."""
    assert motion_time(length, bell_limits(length, duration)) == pytest.approx(duration)


def test_the_bell_follows_the_minimum_jerk_speed() -> None:
    """Within 2.4 % of the peak at every instant, RMS 1.2 %, same peak speed."""
    profile = plan_rest_to_rest(1.0, bell_limits(1.0, 1.0))
    tau = np.linspace(0.0, 1.0, 2001)
    speed = profile.sample(tau * profile.duration).velocity
    reference = minimum_jerk_speed(tau)
    error = np.abs(speed - reference) / PEAK_SPEED
    assert error.max() < 0.024
    assert np.sqrt(np.mean(error**2)) < 0.012
    assert speed.max() == pytest.approx(PEAK_SPEED, rel=1e-6)
