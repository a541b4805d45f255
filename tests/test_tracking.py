"""The tracking report: latency taken out, real following errors kept."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.interpolation import positions_at
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.playback import Samples
from bridge.tracking import MAX_LATENCY, best_latency, executed_states, tracking_report
from shared.robot.postures import forward, rest


@pytest.fixture
def trajectory():  # type: ignore[no-untyped-def]
    return minimum_jerk_trajectory("right", [rest("right"), forward("right")], [0.8])


def _delayed(trajectory, delay: float, hold: float = 0.0) -> Samples:  # type: ignore[no-untyped-def]
    """Samples every 10 ms of the trajectory delayed by ``delay`` [s], each value
    held for ``hold`` [s] (a sensor read once per control cycle)."""
    times = np.arange(0.0, 1.0, 0.01)
    seen = times - delay
    if hold:
        seen = np.floor(seen / hold) * hold
    return Samples(times, positions_at(trajectory, seen))


@pytest.mark.parametrize("delay", [0.0, 0.007, 0.023, 0.041])
def test_a_pure_delay_is_found_and_taken_out(trajectory, delay: float) -> None:  # type: ignore[no-untyped-def]
    """Measured = commanded shifted by a delay: the delay is found to 1 ms and the
    aligned error vanishes, while the unaligned error shows the delay."""
    samples = _delayed(trajectory, delay)
    assert best_latency(trajectory, samples) == pytest.approx(delay, abs=0.0011)
    report = tracking_report(executed_states(trajectory, samples), trajectory)
    assert max(report.tracking_rms_deg.values()) < 0.05
    if delay > 0.02:
        assert max(report.unaligned_rms_deg.values()) > 0.5


def test_a_sample_and_hold_sensor_is_mostly_a_delay(trajectory) -> None:  # type: ignore[no-untyped-def]
    """A 20 ms control cycle reads as ~10 ms of delay; what is left is small."""
    report = tracking_report(
        executed_states(trajectory, _delayed(trajectory, 0.005, hold=0.02)), trajectory
    )
    assert 0.01 <= report.latency <= 0.02
    assert max(report.tracking_rms_deg.values()) < max(
        report.unaligned_rms_deg.values()
    )


def test_a_poor_follower_is_not_hidden(trajectory) -> None:  # type: ignore[no-untyped-def]
    """An arm that only goes 80 % of the way keeps a large error under any shift."""
    samples = _delayed(trajectory, 0.0)
    start = np.asarray(trajectory.positions[0])
    short = Samples(samples.times, start + 0.8 * (samples.positions - start))
    report = tracking_report(executed_states(trajectory, short), trajectory)
    assert max(report.tracking_rms_deg.values()) > 3.0


def test_the_search_stays_within_its_bound(trajectory) -> None:  # type: ignore[no-untyped-def]
    """A delay beyond MAX_LATENCY is not taken out entirely: it shows as error."""
    samples = _delayed(trajectory, MAX_LATENCY + 0.1)
    assert best_latency(trajectory, samples) <= MAX_LATENCY + 1e-12
    report = tracking_report(executed_states(trajectory, samples), trajectory)
    assert max(report.tracking_rms_deg.values()) > 1.0
