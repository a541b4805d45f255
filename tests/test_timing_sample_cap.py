"""The payload cap on a trajectory: measured above 40 000 samples, with advice
that fits how it was made."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import moving_trajectory

from services.timing.sample_cap import (
    FEWER_SAMPLES,
    LOWER_RATE,
    SURELY_SMALL,
    check_asked,
    check_payload,
)
from shared.errors import InvalidInputError
from shared.messages import JointPath, TimingRequest, TimingSegment


def test_a_trajectory_over_the_payload_is_refused_with_the_advice_given() -> None:
    """A 41 000-sample moving arm (about 380 bytes a sample) against a 4 MB
    cap: refused, naming its size, the cap and what to do; the default advice
    is to lower the rate, a wrist path's is to give it fewer samples."""
    trajectory = moving_trajectory(SURELY_SMALL + 1000, np.random.default_rng(1))
    size = len(trajectory.to_json().encode())
    check_payload(trajectory, most=size)  # exactly at the cap: passes
    with pytest.raises(InvalidInputError) as caught:
        check_payload(trajectory, most=4 * 2**20)
    assert caught.value.message.endswith(f"may carry: {LOWER_RATE}")
    assert f"{size / 1e6:.1f} MB of JSON, more than the 4 MiB" in caught.value.message
    assert caught.value.evidence["size"] == size
    with pytest.raises(InvalidInputError, match="resample it at a lower rate"):
        check_payload(trajectory, most=4 * 2**20, advice=FEWER_SAMPLES)


def test_a_short_trajectory_is_not_measured() -> None:
    """At most SURELY_SMALL samples pass unmeasured, whatever the cap."""
    trajectory = moving_trajectory(100, np.random.default_rng(2))
    check_payload(trajectory, most=1)


def _segment(**asked: float) -> TimingSegment:
    """A two-sample right-arm joint path, asked to take ``asked``."""
    names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
    path = JointPath(
        arm="right",
        joint_names=names,
        times=[0.0, 1.0],
        positions=[[0.0] * 5, [0.1] * 5],
        primitives=["S_R", "S_R"],
        wrist=[(0.1, -0.1, 0.0)] * 2,
    )
    return TimingSegment(joint_path=path, **asked)


def test_the_longest_duration_at_100_hz_passes_the_cap() -> None:
    """One segment of 600 s (MAX_DURATION) at 100 Hz is 60 001 samples, both
    ends included: it was refused as "60001 samples ..., more than 60000",
    naming the rate. Over the cap, the error names the one duration or dwell
    asked, and the rate when several make the trajectory long."""
    check_asked(TimingRequest(segments=[_segment(duration=600.0)], rate=100.0))
    with pytest.raises(InvalidInputError, match="would have 600001 samples") as caught:
        check_asked(TimingRequest(segments=[_segment(duration=600.0)], rate=1000.0))
    assert caught.value.field == "segments.0.duration"
    with pytest.raises(InvalidInputError) as caught:
        check_asked(
            TimingRequest(segments=[_segment(), _segment(duration=61.0)], rate=1000.0)
        )
    assert caught.value.field == "segments.1.duration"
    both = [_segment(duration=300.0), _segment(duration=300.0, dwell=1.0)]
    with pytest.raises(InvalidInputError) as caught:
        check_asked(TimingRequest(segments=both, rate=100.0))
    assert caught.value.field == "rate"
