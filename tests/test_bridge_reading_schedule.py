"""The bridge reads the measured angles on a fixed schedule (bridge.playback)."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.playback import SAMPLE_PERIOD, next_reading


def reading_starts(
    round_trips: list[float], period: float = SAMPLE_PERIOD
) -> np.ndarray:
    """When each reading starts [s], each taking its round trip [s], as
    ``play_and_sample`` schedules them (sleeping until the next is due)."""
    now = due = 0.0
    starts = []
    for trip in round_trips:
        starts.append(now)
        now += trip
        due = next_reading(due, period, now)
        now = max(now, due)
    return np.array(starts)


@pytest.mark.parametrize("trip", [0.0005, 0.0033, 0.009])
def test_round_trips_do_not_stretch_the_period(trip: float) -> None:
    """Waiting a period after each answer read at 93.7 Hz in the demo (3.3 ms
    round trips); on the schedule the rate is 100 Hz whatever the round trip,
    as long as it is shorter than the period."""
    starts = reading_starts([trip] * 500)
    np.testing.assert_allclose(np.diff(starts), SAMPLE_PERIOD, rtol=1e-9)


def test_a_slow_answer_brings_no_burst_of_readings() -> None:
    """After an answer 3.5 periods late, the next reading starts as it comes
    and the schedule starts again from there: no run of catch-up readings."""
    trips = [0.002] * 20 + [0.035] + [0.002] * 20
    gaps = np.diff(reading_starts(trips))
    assert gaps[20] == pytest.approx(0.035)
    assert gaps[21] == pytest.approx(0.010)  # a whole period after the late answer
    assert np.all(gaps >= 0.010 - 1e-12)


def test_a_reading_a_little_late_is_caught_up() -> None:
    """An answer less than a period late keeps the schedule: the next reading
    comes at once, and the ones after fall back on the 10 ms grid."""
    trips = [0.002] * 10 + [0.015] + [0.002] * 10
    starts = reading_starts(trips)
    assert starts[11] == pytest.approx(0.115)
    np.testing.assert_allclose(starts[12:], 0.12 + 0.01 * np.arange(len(starts) - 12))
