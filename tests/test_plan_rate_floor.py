"""Plans only at sample rates the robot bridge plays (``MIN_PLAN_RATE``).

The planner took rates from 1 Hz, but the bridge and ``armplan export``
refuse a trajectory whose curve between samples strays from its positions'
own (``bridge.velocity_agreement``): a two-target reach planned at 5 Hz
could not be exported. Any trajectory within the bridge's jerk limits
passes from ``fine_rate``, so the floor is that, rounded up.
"""

from __future__ import annotations

import math

import pytest

from bridge.fidelity import follow_tolerance
from bridge.limits import FrameLimits
from bridge.velocity_agreement import check_velocities, fine_rate
from services.planner.pipeline import plan
from shared.errors import InvalidInputError
from shared.messages import PlanRequest, TimingRequest, TimingSegment, parse
from shared.messages.base import MIN_PLAN_RATE

#: A reach, a hold with the hand closing, a second reach (the hunt's 5 Hz task).
TASK = [
    {"position": (0.12, -0.13, 0.05)},
    {"position": (0.10, -0.2, 0.1), "dwell": 0.3, "hand": "close"},
]


@pytest.mark.parametrize("side", ["right", "left"])
def test_the_floor_is_the_rate_from_which_every_plan_passes(side: str) -> None:
    """``MIN_PLAN_RATE`` is the bridge's ``fine_rate`` over the arm's joints
    and hand, at its highest limits (the most a plan may ask), rounded up:
    15.5 Hz (WristYaw) to 16."""
    limits = FrameLimits.for_arm(side).with_hand(side)
    tolerance = follow_tolerance(limits)
    rates = [fine_rate(j, t) for j, t in zip(limits.jerk, tolerance, strict=True)]
    assert math.ceil(max(rates)) == MIN_PLAN_RATE


def test_a_rate_under_the_floor_is_refused_naming_it() -> None:
    """15.9 Hz is refused, for the plan (before any planning) and for the
    timing stage; 16 Hz passes both."""
    with pytest.raises(InvalidInputError) as caught:
        parse(PlanRequest, {"targets": TASK, "rate": 15.9})
    assert "rate: 15.9 Hz is below the 16 Hz a plan needs" in caught.value.message
    request = parse(PlanRequest, {"targets": TASK, "rate": 16.0})
    segment = TimingSegment(joint_path=plan(request).joint_paths[0])
    timing = {"segments": [segment.model_dump(mode="json")]}
    with pytest.raises(InvalidInputError, match="rate: Input should be greater"):
        parse(TimingRequest, timing | {"rate": 15.9})
    assert parse(TimingRequest, timing | {"rate": 16.0}).rate == 16.0


def test_a_plan_at_the_floor_passes_the_bridges_velocity_check() -> None:
    """The task that could not be exported at 5 Hz, planned at 16 Hz (human
    pace and fastest): its velocities agree with its positions."""
    limits = FrameLimits.for_arm("right")
    for fastest in (False, True):
        request = PlanRequest(targets=TASK, rate=MIN_PLAN_RATE, fastest=fastest)
        trajectory = plan(request).trajectory
        assert trajectory.hand is not None
        check_velocities(trajectory, limits)
