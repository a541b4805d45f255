"""The tracking report: latency taken out, real following errors kept."""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import ValidationError

from bridge.hand import with_hand_joint
from bridge.interpolation import positions_at
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.playback import Samples
from bridge.tracking import (
    MAX_LATENCY,
    best_latency,
    executed_states,
    tracking_report,
    trusted,
)
from shared.demos.min_jerk import minimum_jerk
from shared.messages import ExecutedJointStates
from shared.robot.postures import forward, rest


@pytest.fixture
def trajectory():  # type: ignore[no-untyped-def]
    return minimum_jerk_trajectory("right", [rest("right"), forward("right")], [0.8])


def _delayed(
    trajectory, delay: float, hold: float = 0.0, until: float = 1.0
) -> Samples:  # type: ignore[no-untyped-def]
    """Samples every 10 ms until ``until`` [s] of the trajectory delayed by
    ``delay`` [s], each value held for ``hold`` [s] (a sensor read once per
    control cycle)."""
    times = np.arange(0.0, until, 0.01)
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


def _began_late(trajectory, start_delay: float, lag: float) -> Samples:  # type: ignore[no-untyped-def]
    """A robot that began the call ``start_delay`` [s] after it left (and says
    so) and reports its angles ``lag`` [s] after that, sampled to its end."""
    samples = _delayed(trajectory, start_delay + lag, until=start_delay + lag + 1.0)
    return samples._replace(start_delay=start_delay)


def test_a_measured_start_delay_is_taken_out_beyond_max_latency(trajectory) -> None:  # type: ignore[no-untyped-def]
    """A call that began 0.6 s after it left (a long call over a slow link):
    the search reaches past MAX_LATENCY by the measured start delay and finds
    the whole shift, and the report keeps the start delay."""
    samples = _began_late(trajectory, 0.6, 0.015)
    assert best_latency(trajectory, samples) == pytest.approx(0.615, abs=0.0011)
    states = executed_states(trajectory, samples)
    report = tracking_report(states, trajectory)
    assert states.start_delay == report.start_delay == 0.6
    assert max(report.tracking_rms_deg.values()) < 0.05
    assert max(report.unaligned_rms_deg.values()) > 5.0


def test_a_follower_lagging_past_its_start_still_shows(trajectory) -> None:  # type: ignore[no-untyped-def]
    """The search stops MAX_LATENCY past the measured start: a robot that
    began 0.6 s late and then lags 0.1 s more than that shows its error."""
    samples = _began_late(trajectory, 0.6, MAX_LATENCY + 0.1)
    assert best_latency(trajectory, samples) <= 0.6 + MAX_LATENCY + 1e-12
    report = tracking_report(executed_states(trajectory, samples), trajectory)
    assert max(report.tracking_rms_deg.values()) > 1.0


def _late_readings(trajectory, rng: np.random.Generator, slow: float):  # type: ignore[no-untyped-def]
    """A reader asking every 10 ms (or as soon as the last answer came) a robot
    15 ms late; a share ``slow`` of the answers take 60-200 ms to come back
    although the robot read its angle at once (a busy reader), and each
    sample is stamped in the middle of its round trip."""
    times, seen, trips = [], [], []
    sent = 0.0
    while sent < 1.0:
        fast = rng.uniform() >= slow
        trip = rng.uniform(0.001, 0.004) if fast else rng.uniform(0.06, 0.2)
        times.append(sent + trip / 2)
        seen.append(sent - 0.015)
        trips.append(trip)
        sent = max(sent + 0.01, sent + trip)
    positions = positions_at(trajectory, np.array(seen))
    return Samples(np.array(times), positions, np.array(trips))


def test_readings_with_a_long_round_trip_are_left_out(trajectory) -> None:  # type: ignore[no-untyped-def]
    """Slow readings carry wrong times: compared, they would show errors of
    degrees; left out, the report sees the perfect follower it is given and
    counts them."""
    rng = np.random.default_rng(7)
    samples = _late_readings(trajectory, rng, slow=0.2)
    late = samples.round_trips > 0.05
    assert late.sum() >= 5
    states = executed_states(trajectory, samples)
    report = tracking_report(states, trajectory)
    assert report.discarded == late.sum()
    assert report.samples == len(samples.times) - late.sum()
    assert report.time_uncertainty <= 0.002 + 1e-12
    assert max(report.tracking_rms_deg.values()) < 0.1
    assert report.latency == pytest.approx(0.015, abs=0.0025)
    everything = tracking_report(states.model_copy(update={"round_trips": []}))
    assert everything.discarded == 0
    assert max(everything.tracking_rms_deg.values()) > 5 * max(
        report.tracking_rms_deg.values()
    )
    assert states.round_trips == samples.round_trips.tolist()


def test_when_most_readings_are_slow_the_faster_half_is_compared(trajectory) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(8)
    samples = _late_readings(trajectory, rng, slow=0.8)
    count = len(samples.times)
    assert (samples.round_trips <= 0.02).sum() < count / 2
    keep = trusted(samples.round_trips, count)
    assert keep.sum() == (count + 1) // 2
    assert np.max(samples.round_trips[keep]) <= np.min(samples.round_trips[~keep])
    report = tracking_report(executed_states(trajectory, samples), trajectory)
    assert report.samples == (count + 1) // 2
    assert report.discarded == count - report.samples
    assert report.time_uncertainty >= 0.03


@pytest.mark.parametrize("delay", [0.0, 0.023])
def test_the_delay_is_fitted_on_the_arm_not_the_hand(trajectory, delay: float) -> None:  # type: ignore[no-untyped-def]
    """The hand closes while the arm reaches, and an object it grasps holds
    it at 0.6 open: the arm's delay is still found to 1 ms, the arm's
    aligned error vanishes, and the hand's error (its command aligned with
    the arm's delay) is what the object held back, 0.6. With the hand's
    open fraction in the fit, the held hand pulled the delay 36 ms too long
    (0.036 s for none, 0.059 s for 0.023 s)."""
    t = np.asarray(trajectory.times)
    closing = 1.0 - minimum_jerk((t - t[0]) / (t[-1] - t[0]))
    with_hand = with_hand_joint(
        trajectory.model_copy(update={"hand": closing.tolist()})
    )
    samples = _delayed(with_hand, delay)
    samples = samples._replace(
        positions=np.column_stack(
            [samples.positions[:, :-1], np.maximum(samples.positions[:, -1], 0.6)]
        )
    )
    assert best_latency(with_hand, samples) == pytest.approx(delay, abs=0.0011)
    report = tracking_report(executed_states(with_hand, samples), with_hand)
    assert max(report.tracking_rms_deg.values()) < 0.05
    assert report.hand_tracking_max == pytest.approx(0.6, abs=1e-3)


def test_round_trips_must_match_the_samples(trajectory) -> None:  # type: ignore[no-untyped-def]
    states = executed_states(trajectory, _delayed(trajectory, 0.0))
    with pytest.raises(ValidationError, match="round_trips has 3 values"):
        ExecutedJointStates.model_validate(
            states.model_dump() | {"round_trips": [0.01, 0.01, 0.01]}
        )
