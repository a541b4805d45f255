"""Minimum-jerk trajectories through postures: bad input is a typed error
naming it, and every duration is kept as given."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bridge.minimum_jerk import PEAK_SPEED, minimum_jerk_trajectory
from shared.errors import InvalidInputError
from shared.robot import load_arm
from shared.robot.postures import rest

A = [1.57, -0.1, 1.57, 0.2, 0.0]
B = [1.0, -0.3, 1.2, 0.5, 0.0]


@pytest.mark.parametrize("duration", [0.004, 0.0, -1.0, math.nan, math.inf])
def test_a_duration_it_cannot_sample_is_refused_naming_it(duration: float) -> None:
    """Under one sample (0.004 s at 100 Hz), zero or negative: IndexError
    before; NaN: ValueError. Now InvalidInputError naming the duration."""
    with pytest.raises(InvalidInputError) as caught:
        minimum_jerk_trajectory("right", [A, B], [duration])
    assert caught.value.field == "durations"
    assert caught.value.message.startswith(f"durations[0] is {duration!r} s")
    assert "at least one sample (0.01 s at 100 Hz)" in caught.value.message


def test_a_duration_off_the_sample_grid_is_kept() -> None:
    """0.333 s at 100 Hz became 0.33 s; now 34 equal steps end at 0.333 s,
    each under 1/100 s, and the segment still peaks at PEAK_SPEED |d| / T."""
    trajectory = minimum_jerk_trajectory("right", [A, B], [0.333])
    times = np.array(trajectory.times)
    assert trajectory.duration == pytest.approx(0.333, abs=1e-15)
    assert len(times) == 35
    steps = np.diff(times)
    np.testing.assert_allclose(steps, 0.333 / 34, rtol=1e-12)
    speed = np.abs(np.array(trajectory.velocities)).max(axis=0)
    expected = PEAK_SPEED * np.abs(np.subtract(B, A)) / 0.333
    np.testing.assert_allclose(speed, expected, rtol=1e-3)
    np.testing.assert_allclose(trajectory.positions[-1], B, atol=1e-12)


def test_a_whole_number_of_samples_stays_on_the_rate() -> None:
    """0.6 s and 0.5 s at 100 Hz: samples at k / 100 exactly, as before."""
    trajectory = minimum_jerk_trajectory("right", [A, B, A], [0.6, 0.5])
    np.testing.assert_array_equal(trajectory.times[:61], np.arange(61) / 100.0)
    assert trajectory.duration == pytest.approx(1.1, abs=1e-12)
    assert len(trajectory.times) == 111


def test_a_posture_outside_the_ranges_is_refused_naming_the_joint() -> None:
    """The bridge refused it later; the function itself refuses it now."""
    limits = load_arm("right").limits
    beyond = np.array(rest("right"))
    beyond[3] = limits.upper[3] + 0.01
    with pytest.raises(InvalidInputError) as caught:
        minimum_jerk_trajectory("right", [rest("right"), beyond], [0.5])
    assert caught.value.field == "postures"
    assert caught.value.message.startswith(f"postures[1]: {limits.names[3]} at")
    assert "outside its range" in caught.value.message


@pytest.mark.parametrize(
    ("postures", "durations", "rate", "field"),
    [
        ([A], [], 100.0, "postures"),
        ([A, B[:4]], [0.5], 100.0, "postures"),
        ([A, [math.nan] * 5], [0.5], 100.0, "postures"),
        ([A, B], [0.5, 0.5], 100.0, "durations"),
        ([A, B], [0.5], 0.0, "rate"),
        ([A, B], [0.5], math.nan, "rate"),
    ],
)
def test_malformed_input_is_a_typed_error(
    postures: list, durations: list, rate: float, field: str
) -> None:
    """Shapes, non-finite angles and rates are named, not numpy errors."""
    with pytest.raises(InvalidInputError) as caught:
        minimum_jerk_trajectory("right", postures, durations, rate)
    assert caught.value.field == field
