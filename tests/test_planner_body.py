"""The planner keeps the arm clear of NAO's own body (``shared.robot.body``).

A target in the body is refused before any planning, by ``plan`` and ``ik``
alike and from the command line; a wrist path with a sample there is
refused naming that sample; a reach whose every end is clear but whose
arm comes near the body on the way turns its elbow clear, or is refused
naming the first sample too near; and every plan that is made keeps
clear, over random reaches.
"""

from __future__ import annotations

import numpy as np
import pytest

from services.ik import solve_request
from services.planner.pipeline import LocalStages, plan, track_movement
from services.planner.reach_path import reach_wrist_path
from shared.errors import ArmplanError, BodyCollisionError, TargetInBodyError
from shared.messages import IKRequest, Method, PlanRequest, ReachTarget
from shared.robot import load_arm
from shared.robot.body import HAND, MARGIN, closest, point_clearance
from shared.robot.fk_many import key_points
from shared.robot.postures import mirror
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


#: From the arm low and turned out to a target beside the head: every
#: sample of the wrist path is clear of the body, but the upper arm, as the
#: stages track it, comes within the margin of the head on the way.
NEAR_HEAD = ([1.733, -0.603, -1.809, 0.562, 0.09], [0.0794, -0.0986, 0.1966])
#: From a clear posture to a target low beside the pelvis: the hand, which
#: points along the forearm, ends 38 mm into the pelvis, and no swivel tried
#: takes it out.
INTO_PELVIS = (
    [-1.9535, -0.9124, 1.5086, 0.5785, 1.5343],
    [-0.0482, -0.0653, -0.0109],
)


def _tracked(side: str, start: list[float], target: list[float]) -> np.ndarray:
    """The stages' own joint path for the reach, before the planner's check."""
    arm = load_arm(side)
    path = reach_wrist_path(arm, np.array(start), ReachTarget(position=target))
    joint_path, _ = track_movement(
        LocalStages(), path, np.array(start), Method.MP, None
    )
    return np.array(joint_path.positions)


@pytest.mark.parametrize("side", ["right", "left"])
def test_a_reach_whose_arm_comes_near_the_body_turns_its_elbow_clear(side) -> None:
    """The stages' joint path brings the upper arm within the margin of the
    head; the planner turns the elbow about the wrist's path (its swivel)
    and plans it: every sample keeps the margin, the wrist stays where the
    stages put it, the arm starts where it is, and the elbow did turn. The
    left arm's mirror image does the same."""
    arm = load_arm(side)
    start, target = NEAR_HEAD
    if side == "left":
        start, target = (
            mirror(np.array(start)).tolist(),
            [target[0], -target[1], target[2]],
        )
    assert closest(arm, [start]).clearance > MARGIN
    assert point_clearance(target, HAND)[1] > MARGIN
    assert closest(arm, _tracked(side, start, target)).clearance < MARGIN
    result = plan(PlanRequest(arm=side, start=start, targets=[{"position": target}]))
    assert closest(arm, result.trajectory.positions).clearance >= MARGIN
    turned, before = (
        key_points(arm, result.joint_paths[0].positions),
        key_points(arm, _tracked(side, start, target)),
    )
    assert np.abs(turned["wrist"] - before["wrist"]).max() < 1e-4
    assert np.allclose(result.trajectory.positions[0], start)
    assert np.linalg.norm(turned["elbow"] - before["elbow"], axis=1).max() > 0.005


def test_the_refusal_names_the_movement_the_turn_failed_for() -> None:
    """Two reaches: the first is taken clear by the swivel, the second
    (into the pelvis) is not; the refusal's sample lies in the second
    movement and says the turn was tried."""
    start, first = NEAR_HEAD
    request = PlanRequest(
        arm="right",
        start=start,
        targets=[{"position": first}, {"position": INTO_PELVIS[1]}],
    )
    with pytest.raises(BodyCollisionError, match=r"NAO's pelvis") as err:
        plan(request)
    alone = plan(PlanRequest(arm="right", start=start, targets=[{"position": first}]))
    assert err.value.time > alone.trajectory.times[-1]
    assert "turning the elbow about the wrist's path" in str(err.value)


def test_a_reach_no_swivel_takes_clear_is_refused_saying_so() -> None:
    """The hand into the pelvis at the goal: refused as before, the error
    saying that turning the elbow was tried."""
    start, target = INTO_PELVIS
    assert closest(load_arm("right"), [start]).clearance > MARGIN
    request = PlanRequest(arm="right", start=start, targets=[{"position": target}])
    with pytest.raises(BodyCollisionError, match=r"hand .* NAO's pelvis") as err:
        plan(request)
    assert "turning the elbow about the wrist's path" in str(err.value)
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


#: A reach whose tracked arm comes 4 mm from the pelvis (the hand) while its
#: wrist path keeps clear; 0.3 s long as planned, 31 samples.
NEAR_PELVIS = ([1.3115, -0.6736, -0.1352, 1.2465, 0.641], (0.058, -0.084, -0.0073))


@pytest.mark.parametrize(("slower", "made"), [(5.0, True), (3.0, False)])
def test_a_given_wrist_path_turns_its_elbow_if_its_times_allow(
    slower: float, made: bool
) -> None:
    """The reach's wrist path given to plan at its times slowed 5 times: the
    elbow is turned and the plan keeps the margin, the wrist on the path;
    slowed only 3 times the turn would need more speed than the times
    allow, and the refusal says so."""
    arm = load_arm("right")
    start, target = NEAR_PELVIS
    path = reach_wrist_path(arm, np.array(start), ReachTarget(position=target))
    path = path.model_copy(update={"times": [t * slower for t in path.times]})
    assert closest(arm, _tracked("right", start, list(target))).clearance < MARGIN
    request = PlanRequest(arm="right", start=start, wrist_path=path)
    if not made:
        with pytest.raises(BodyCollisionError, match="needs more speed than the"):
            plan(request)
        return
    result = plan(request)
    assert closest(arm, result.trajectory.positions).clearance >= MARGIN
    wrists = key_points(arm, result.trajectory.positions)["wrist"]
    assert np.abs(wrists - np.array(path.positions)).max() < 1e-3
    assert result.trajectory.times == pytest.approx(path.times)
