"""The sample-rate check: times in seconds pass, milliseconds are named."""

from __future__ import annotations

import numpy as np
import pytest

from shared.demos.sample_rate import (
    MIN_CAPTURE_RATE,
    check_capture_rate,
    check_one_rate,
    check_seconds,
)
from shared.demos.trial import Trial
from shared.errors import InvalidInputError
from shared.messages.motion_model import MAX_SAMPLE_RATE, MIN_SAMPLE_RATE
from shared.robot.side import Side


@pytest.mark.parametrize("rate", [MIN_SAMPLE_RATE, 100.0, MAX_SAMPLE_RATE])
def test_rates_in_the_model_range_are_returned(rate: float) -> None:
    """1, 100 and 10 000 Hz are seconds: the rate comes back."""
    times = np.arange(20) / rate
    assert check_seconds([times], "trial 0") == pytest.approx(rate)


def test_the_rate_is_the_median_of_every_trials_wide_steps() -> None:
    """Each trial's steps across half of it count, all trials' together:
    two trials of 0.01 s steps and one of 0.02 s read 100 Hz; two of 0.02 s
    and one of 0.01 s, 50 Hz."""
    fine, coarse = np.arange(11) * 0.01, np.arange(11) * 0.02
    rate = check_seconds([fine, fine, coarse], "the demonstrations")
    assert rate == pytest.approx(100.0)
    rate = check_seconds([coarse, fine, coarse], "the demonstrations")
    assert rate == pytest.approx(50.0)


def test_a_last_sample_off_the_grid_leaves_the_rate() -> None:
    """80 steps of 0.01 s, the last sample 5 ms late (a synthetic reach ends
    at its duration): 100 Hz (over the span, 99.4 Hz; a least-squares step,
    99.98 Hz)."""
    times = np.arange(81) / 100.0
    times[-1] += 0.005
    assert check_seconds([times], "trial 0") == pytest.approx(100.0, rel=1e-9)


@pytest.mark.parametrize("rate", [120.0, 150.0, 240.0])
def test_times_rounded_to_milliseconds_keep_their_rate(rate: float) -> None:
    """A second at 120, 150 or 240 Hz written to the millisecond reads within
    0.1 % of its rate (the median step read 125, 142.9 and 250 Hz)."""
    times = np.round(np.arange(int(rate) + 1) / rate, 3)
    assert check_seconds([times], "trial 0") == pytest.approx(rate, rel=1e-3)


def test_a_csv_rounded_to_milliseconds_is_one_rate_with_its_c3d() -> None:
    """The same 120 Hz session, exact (C3D) and to the millisecond (CSV):
    one rate; 100 and 120 Hz are still two."""
    exact = np.arange(121) / 120.0

    def trial(times: np.ndarray, source: str) -> Trial:
        still = np.zeros((len(times), 3))
        return Trial(
            "P01", 0, 0, Side.RIGHT, times, still, still, still, None,
            still[-1], None, source,
        )  # fmt: skip

    rounded = trial(np.round(exact, 3), "s.csv")
    check_one_rate([trial(exact, "s.c3d"), rounded])
    with pytest.raises(InvalidInputError, match=r"s\.c3d at 100 Hz; s\.csv at 120"):
        check_one_rate([trial(np.arange(101) / 100.0, "s.c3d"), rounded])


def test_milliseconds_are_named_with_what_to_do() -> None:
    """A 100 Hz trial in milliseconds: the message says divide by 1000."""
    with pytest.raises(InvalidInputError) as info:
        check_seconds([10.0 * np.arange(5)], "trial 2")
    assert info.value.message == (
        "trial 2: the times step 10 apart (median), a sample rate of 0.1 Hz if "
        "they are seconds; demonstrations are sampled at 1 to 10000 Hz: these "
        "look like milliseconds: divide them by 1000 (times are in seconds)"
    )
    assert info.value.evidence["rate"] == pytest.approx(0.1)


@pytest.mark.parametrize("step", [1e-5, 1e4])
def test_other_units_are_refused_without_the_milliseconds_hint(step: float) -> None:
    """100 kHz, or a step of hours that milliseconds cannot explain, is
    refused saying only that times are in seconds."""
    with pytest.raises(InvalidInputError) as info:
        check_seconds([step * np.arange(5)], "trial 0")
    assert info.value.message.endswith(": times must be in seconds")
    assert "milliseconds" not in info.value.message


@pytest.mark.parametrize("rate", [MIN_SAMPLE_RATE, 10.0, 19.0])
def test_a_rate_below_any_capture_asks_for_frame_numbers(rate: float) -> None:
    """Frame numbers (0, 1, 2, ...) read as seconds make 1 Hz, which the
    model's range lets by: refused, asking if they are frame numbers."""
    with pytest.raises(InvalidInputError) as info:
        check_capture_rate(np.arange(137) / rate, "trial 0 (lines 2-138)")
    assert info.value.message == (
        f"trial 0 (lines 2-138): the times step {1 / rate:.4g} s apart "
        f"(median), a sample rate of {rate:.4g} Hz; motion capture samples at "
        "20 Hz or more: are these frame numbers? Times must be in seconds (a "
        "frame's number over the capture's rate)"
    )
    assert info.value.evidence["rate"] == pytest.approx(rate)


@pytest.mark.parametrize("rate", [MIN_CAPTURE_RATE, 120.0, MAX_SAMPLE_RATE])
def test_capture_rates_pass(rate: float) -> None:
    """20 Hz and up are a capture's rates: no error."""
    check_capture_rate(np.arange(50) / rate, "trial 0")
