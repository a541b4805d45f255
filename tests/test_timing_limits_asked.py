"""A request's own acceleration and jerk limits (``TimingLimits``): kept, and
never above the bridge's safety net."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.checked_frames import checked_frames
from bridge.limits import FrameLimits
from services.planner.pipeline import plan
from shared.errors import InvalidInputError, LimitViolationError
from shared.messages import PlanRequest, Trajectory, WristPath, parse
from shared.robot import load_arm
from shared.robot.motion_limits import (
    SLOWEST_ACCELERATION,
    SLOWEST_JERK,
    motion_limits,
    net_limits,
)
from shared.robot.postures import rest

GOAL = [0.12, -0.13, 0.05]


def planned(**fields: object) -> Trajectory:
    return plan(
        parse(PlanRequest, {"targets": [{"position": GOAL}]} | fields)
    ).trajectory


def peaks(trajectory: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """Largest |acceleration| [rad/s^2] and |jerk| [rad/s^3] per joint, the
    jerk from the sampled accelerations' differences."""
    acc = np.array(trajectory.accelerations)
    dt = np.diff(trajectory.times)[:, None]
    return np.abs(acc).max(axis=0), (np.abs(np.diff(acc, axis=0)) / dt).max(axis=0)


def test_lower_limits_are_kept_and_make_the_fastest_reach_longer() -> None:
    """With 5 rad/s^2 and 40 rad/s^3 for every joint, no joint goes over
    either (the default allows about 23 and 460 here), and the fastest reach
    takes longer than with the defaults."""
    default = planned(fastest=True)
    gentle = planned(fastest=True, limits={"acceleration": 5.0, "jerk": 40.0})
    acc, jerk = peaks(gentle)
    assert acc.max() <= 5.0 * (1 + 1e-6) and jerk.max() <= 40.0 * (1 + 1e-6)
    assert peaks(default)[0].max() > 10.0
    assert gentle.times[-1] > 1.5 * default.times[-1]


def test_five_values_are_one_per_joint() -> None:
    """Only ShoulderPitch's acceleration lowered: it keeps 2 rad/s^2, while
    another joint goes above that."""
    arm = load_arm("right")
    default = motion_limits(arm.limits).acceleration
    asked = [2.0, *default[1:]]
    acc, _ = peaks(planned(fastest=True, limits={"acceleration": asked}))
    assert acc[0] <= 2.0 * (1 + 1e-6)
    assert acc[1:].max() > 2.0


def test_a_given_acceleration_sets_the_default_jerk() -> None:
    """Acceleration given alone: the jerk limit is that acceleration / 0.05 s,
    not the default acceleration's (here 4 / 0.05 = 80 rad/s^3)."""
    _, jerk = peaks(planned(fastest=True, limits={"acceleration": 4.0}))
    assert jerk.max() <= 80.0 * (1 + 1e-6)


@pytest.mark.parametrize(
    ("limits", "field", "joint"),
    [
        ({"acceleration": 80.0}, "acceleration", "RShoulderRoll"),
        ({"jerk": [100.0, 100.0, 100.0, 100.0, 1e6]}, "jerk", "RWristYaw"),
    ],
)
def test_limits_above_the_safety_net_are_refused(
    limits: dict[str, object], field: str, joint: str
) -> None:
    """Above the bridge's net the bridge would refuse the trajectory; the
    planner refuses the request, naming the joint and the net."""
    with pytest.raises(InvalidInputError) as error:
        planned(limits=limits)
    assert error.value.field == field
    assert joint in error.value.message and "safety net" in error.value.message


@pytest.mark.parametrize(
    ("limits", "field", "joint"),
    [
        ({"acceleration": 1e-6}, "acceleration", "RShoulderPitch"),
        ({"acceleration": 1e-300}, "acceleration", "RShoulderPitch"),
        ({"jerk": [100.0, 100.0, 100.0, 100.0, 1.0]}, "jerk", "RWristYaw"),
    ],
)
def test_limits_below_their_floor_are_refused_before_planning(
    limits: dict[str, object], field: str, joint: str
) -> None:
    """1e-6 rad/s^2 made a 2.7 million-sample trajectory (2 GB) before the
    sample cap refused it, 1e-9 took 22 GB, 1e-300 overflowed; a hundredth of
    the default acceleration (a thousandth of the jerk) is the floor."""
    with pytest.raises(InvalidInputError) as error:
        planned(limits=limits)
    assert error.value.field == field
    assert joint in error.value.message and "below the" in error.value.message


def test_limits_at_their_floor_plan_a_slow_reach() -> None:
    """At the floors (per joint) a reach is planned, within them, slowly."""
    default = motion_limits(load_arm("right").limits)
    floors = {
        "acceleration": list(default.acceleration / SLOWEST_ACCELERATION),
        "jerk": list(default.jerk / SLOWEST_JERK),
    }
    slow = planned(fastest=True, limits=floors)
    acc, jerk = peaks(slow)
    assert np.all(acc <= np.array(floors["acceleration"]) * (1 + 1e-6))
    assert np.all(jerk <= np.array(floors["jerk"]) * (1 + 1e-6))
    assert 2.0 < slow.times[-1] < 20.0


@pytest.mark.parametrize(
    ("limits", "words"),
    [
        ({"jerk": [1.0, 2.0]}, "not 2"),
        ({"acceleration": -1.0}, "positive"),
        ({"acceleration": 0.0}, "positive"),
        ({"speed": 1.0}, "Extra inputs"),
    ],
)
def test_malformed_limits_are_invalid_input(
    limits: dict[str, object], words: str
) -> None:
    with pytest.raises(InvalidInputError) as error:
        parse(PlanRequest, {"targets": [{"position": GOAL}], "limits": limits})
    assert words in error.value.message


def test_limits_at_the_net_pass_the_bridges_checks() -> None:
    """The highest limits allowed make frames the bridge sends, at its rates."""
    net = net_limits(load_arm("right").limits)
    asked = {"acceleration": list(net.acceleration), "jerk": list(net.jerk)}
    trajectory = planned(fastest=True, limits=asked)
    assert peaks(trajectory)[0].max() > 0.5 * net.acceleration.min()
    for rate in (25.0, 50.0, 100.0):
        checked_frames(trajectory, rate, FrameLimits.for_arm("right"))


def test_a_wrist_path_is_checked_against_the_asked_limits() -> None:
    """A wrist path the default limits allow is refused under lower ones:
    its own times are kept, so it cannot be slowed down to fit. (The
    planner's reach path at its own times, 0.64 s, is too fast for the
    default jerk limit on the curve the robot plays, 689 > 661 rad/s^3;
    at twice its times it is not.)"""
    start = plan(parse(PlanRequest, {"targets": [{"position": GOAL}]}))
    path = WristPath(
        arm="right",
        times=[2.0 * t for t in start.wrist_paths[0].times],
        positions=start.wrist_paths[0].positions,
    )
    begin = list(rest("right"))
    fine = parse(PlanRequest, {"wrist_path": path, "start": begin})
    assert plan(fine).trajectory.times == path.times
    slow = parse(
        PlanRequest, {"wrist_path": path, "start": begin, "limits": {"jerk": 5.0}}
    )
    with pytest.raises(LimitViolationError):
        plan(slow)


#: Seven of the demo task's targets, in its order.
SEVEN = [
    (0.14, -0.1, 0.06), (0.1, -0.17, 0.02), (0.11, -0.07, 0.01), (0.13, -0.07, 0.09),
    (0.12, -0.165, 0.03), (0.06, -0.16, 0.22), (0.06, -0.11, 0.23),
]  # fmt: skip


def test_a_trajectory_too_large_for_the_bus_is_refused_by_the_planner() -> None:
    """46 targets at 1000 Hz and 3 rad/s^2: 58 197 samples, under the sample
    cap, but 19.9 MB of JSON; it planned, and the bridge then refused it as
    payload_too_large. The planner now refuses it, saying its size."""
    targets = [{"position": SEVEN[k % len(SEVEN)]} for k in range(46)]
    with pytest.raises(InvalidInputError) as error:
        plan(
            parse(
                PlanRequest,
                {"targets": targets, "rate": 1000, "limits": {"acceleration": 3.0}},
            )
        )
    assert "MB of JSON, more than the 16 MiB" in error.value.message
    assert error.value.evidence["size"] > error.value.evidence["limit"]
