"""The sample-rate check: times in seconds pass, milliseconds are named."""

from __future__ import annotations

import numpy as np
import pytest

from shared.demos.sample_rate import check_seconds
from shared.errors import InvalidInputError
from shared.messages.motion_model import MAX_SAMPLE_RATE, MIN_SAMPLE_RATE


@pytest.mark.parametrize("rate", [MIN_SAMPLE_RATE, 100.0, MAX_SAMPLE_RATE])
def test_rates_in_the_model_range_are_returned(rate: float) -> None:
    """1, 100 and 10 000 Hz are seconds: the median rate comes back."""
    times = np.arange(20) / rate
    assert check_seconds([times], "trial 0") == pytest.approx(rate)


def test_the_rate_is_one_over_the_median_step_of_every_trial() -> None:
    """Steps of all trials count: 0.01 s twice and 0.02 s once give 100 Hz,
    whatever one odd step (a dropped frame) does."""
    times = [np.array([0.0, 0.01, 0.02]), np.array([0.0, 0.02])]
    assert check_seconds(times, "the demonstrations") == pytest.approx(100.0)


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
