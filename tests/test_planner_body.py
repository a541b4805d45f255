"""The planner keeps the arm clear of NAO's own body (``shared.robot.body``).

A target in the body is refused before any planning, by ``plan`` and ``ik``
alike and from the command line; a wrist path with a sample there is
refused naming that sample; a reach whose every end is clear but whose
movement is not is refused naming the first sample too near; and every
plan that is made keeps clear, over random reaches.
"""

from __future__ import annotations

import numpy as np
import pytest

from services.ik import solve_request
from services.planner.pipeline import plan
from shared.errors import ArmplanError, BodyCollisionError, TargetInBodyError
from shared.messages import IKRequest, PlanRequest
from shared.robot import load_arm
from shared.robot.body import HAND, MARGIN, closest, point_clearance
from tests.armplan_cli import armplan

#: Within the right arm's reach shell, in the chest.
IN_CHEST = (0.03, 0.0, 0.02)
#: The right hand folded back into the chest (3.4 mm into the torso).
FOLDED = (0.0, 0.3, 0.0, 1.54, 0.0)


def test_a_target_in_the_chest_is_refused_before_any_planning() -> None:
    with pytest.raises(TargetInBodyError, match="inside NAO's torso") as err:
        plan(PlanRequest(arm="right", targets=[{"position": IN_CHEST}]))
    assert err.value.kind == "target_in_body"
    with pytest.raises(TargetInBodyError):  # the ik service's own check
        solve_request(load_arm("right"), IKRequest(arm="right", target=IN_CHEST))


@pytest.mark.parametrize("command", ["plan", "ik"])
def test_the_command_line_says_which_part_of_the_body(command: str) -> None:
    done = armplan(command, "--target", *(str(v) for v in IN_CHEST))
    assert done.returncode == 1, done.stderr
    assert "is inside NAO's torso" in done.stderr
    assert "Traceback" not in done.stderr


def test_a_start_posture_in_the_body_is_refused_before_any_planning() -> None:
    """The hand folded back into the chest: the start is named, not a target."""
    request = PlanRequest(
        arm="right", start=FOLDED, targets=[{"position": (0.15, -0.10, 0.05)}]
    )
    with pytest.raises(BodyCollisionError, match=r"^the start posture brings") as err:
        plan(request)
    assert "nothing was planned" in str(err.value)
    assert err.value.body_part == "torso" and err.value.arm_part == "hand"
    assert err.value.clearance == pytest.approx(
        closest(load_arm("right"), [FOLDED]).clearance
    )


def test_a_wrist_path_into_the_chest_is_refused_at_its_first_sample_there() -> None:
    """A minimum-jerk line from in front of the right shoulder to the
    chest's front: refused at the first sample where a hand there would
    come within the margin, with its time."""
    start, end = np.array([0.13, -0.09, 0.05]), np.array([0.075, 0.0, 0.05])
    times = np.linspace(0.0, 1.5, 151)
    u = times / 1.5
    blend = 10 * u**3 - 15 * u**4 + 6 * u**5
    positions = start + blend[:, None] * (end - start)
    request = PlanRequest(
        arm="right",
        wrist_path={"times": times.tolist(), "positions": positions.tolist()},
    )
    with pytest.raises(TargetInBodyError, match=r"wrist-path sample \d+") as err:
        plan(request)
    gaps = [point_clearance(p, HAND)[1] for p in positions]
    first = next(k for k, gap in enumerate(gaps) if gap < MARGIN)
    assert f"wrist-path sample {first} (t = {times[first]:.3f} s)" in str(err.value)
    assert err.value.clearance == pytest.approx(gaps[first])


def test_a_reach_whose_wrist_path_is_clear_but_whose_arm_is_not_is_refused() -> None:
    """From the arm low and turned out to a target beside the head: every
    sample of the wrist path is clear of the body, but the upper arm comes
    within the margin of the head on the way."""
    start = [1.733, -0.603, -1.809, 0.562, 0.09]
    target = [0.0794, -0.0986, 0.1966]
    arm = load_arm("right")
    assert closest(arm, [start]).clearance > MARGIN
    assert point_clearance(target, HAND)[1] > MARGIN
    request = PlanRequest(arm="right", start=start, targets=[{"position": target}])
    with pytest.raises(BodyCollisionError, match=r"upper arm .* NAO's head") as err:
        plan(request)
    assert err.value.arm_part == "upper arm"
    assert err.value.clearance < MARGIN
    assert err.value.time == pytest.approx(err.value.index / request.rate)


def test_every_plan_made_keeps_clear_of_the_body() -> None:
    """Random reaches from rest to targets within the reach, clear of the
    body: every plan the planner makes keeps the margin in every sample;
    the others are refused with a typed error. Most are made, so the check
    means something."""
    arm = load_arm("right")
    rng = np.random.default_rng(11)
    low, high = arm.reach
    shoulder = arm.fk(np.zeros(5)).shoulder
    made = tried = 0
    while tried < 20:
        direction = rng.normal(size=3)
        direction[0] = abs(direction[0])  # in front of the shoulder
        direction /= np.linalg.norm(direction)
        target = shoulder + rng.uniform(low + 0.005, high - 0.005) * direction
        if point_clearance(target, HAND)[1] < 2 * MARGIN:
            continue
        tried += 1
        try:
            result = plan(
                PlanRequest(arm="right", targets=[{"position": target.tolist()}])
            )
        except ArmplanError:
            continue
        made += 1
        near = closest(arm, result.trajectory.positions)
        assert near.clearance >= MARGIN, (target, near)
    assert made >= 15


@pytest.mark.parametrize(
    ("joints", "expected"),
    [
        ((1.5708, -0.1, 1.5708, 0.2, 0.0), "clear of NAO's body by 23.3 mm"),
        ((0.0, 0.3, 0.0, 1.5, 0.0), "the planner refuses it"),
        ((0.0, 0.3, 0.0, 1.54, 0.0), "in NAO's body: 3.4 mm deep (hand to torso)"),
    ],
)
def test_fk_says_how_near_the_body_a_posture_is(joints, expected) -> None:
    """The hanging arm, the hand folded back to within the margin of the
    chest, and into it: fk's last line says which, with the model's
    numbers (``closest``)."""
    done = armplan("fk", "--joints", *(str(v) for v in joints))
    assert done.returncode == 0, done.stderr
    last = done.stdout.strip().splitlines()[-1]
    assert expected in last
    near = closest(load_arm("right"), [joints])
    assert f"{abs(near.clearance) * 1000:.1f} mm" in last
