"""Turning the elbow about the wrist's path to keep clear of the body
(services/planner/clear_swivel.py, services/ik/elbow_turn.py): the profile,
the rotation, the turn."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation  # type: ignore[import-untyped]

from services.ik.elbow_turn import least_clearances, rotate, turn_elbow
from services.planner.clear_swivel import RAMP, STEP, keep_clear, swivel_profile
from services.planner.pipeline import LocalStages, track_movement
from services.planner.reach_path import reach_wrist_path
from shared.geometry.palm import roll_error
from shared.geometry.swivel import swivel_angle
from shared.messages import Method, ReachTarget
from shared.robot import load_arm
from shared.robot.body import MARGIN
from shared.robot.fk_many import key_points
from tests.clear_draws import clear_posture

TIMES = np.arange(101) * 0.01


def _near(first: int, last: int, n: int = len(TIMES)) -> np.ndarray:
    near = np.zeros(n, dtype=bool)
    near[first : last + 1] = True
    return near


@pytest.mark.parametrize(
    ("first", "last"), [(40, 60), (2, 30), (70, 100), (0, 100), (1, 3)]
)
def test_the_profile_is_full_where_near_and_rises_smoothly_from_the_start(
    first: int, last: int
) -> None:
    """0 at the first sample (the arm is there), within 0..1, never steeper
    than a minimum-jerk ramp of RAMP (peak slope 1.875 / RAMP), full over
    the near samples a ramp fits before, and held full to the end when the
    near samples reach it."""
    weight = swivel_profile(TIMES, _near(first, last))
    assert weight.max() == 1.0  # near samples early on: full once the ramp ends
    assert weight[0] == 0.0
    assert np.all((weight >= 0.0) & (weight <= 1.0))
    slope = np.abs(np.diff(weight)) / np.diff(TIMES)
    assert slope.max() <= 1.875 / RAMP + 1e-9
    ramp_end = first if TIMES[first] >= RAMP else round(RAMP / 0.01)
    assert np.all(weight[max(ramp_end, first) : last + 1] == 1.0)
    if last == len(TIMES) - 1:
        assert weight[-1] == 1.0
    else:
        assert weight[-1] == 0.0


def test_the_profile_is_zero_away_from_the_near_samples() -> None:
    weight = swivel_profile(TIMES, _near(50, 55))
    assert np.all(weight[: 50 - 15] == 0.0)
    assert np.all(weight[55 + 16 :] == 0.0)


def test_rotate_agrees_with_scipy_and_keeps_what_a_rotation_keeps() -> None:
    """Rodrigues' formula against scipy's rotation vector, over random
    vectors, axes and angles; lengths and the part along the axis kept;
    a turn and its opposite undo each other."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        v, axis = rng.normal(size=3), rng.normal(size=3)
        angle = rng.uniform(-math.pi, math.pi)
        turned = rotate(v, axis, angle)
        unit = axis / np.linalg.norm(axis)
        expected = Rotation.from_rotvec(angle * unit).apply(v)
        assert np.allclose(turned, expected, atol=1e-12)
        assert np.linalg.norm(turned) == pytest.approx(np.linalg.norm(v))
        assert turned @ unit == pytest.approx(v @ unit)
        assert np.allclose(rotate(turned, axis, -angle), v, atol=1e-12)


def test_turning_the_elbow_keeps_the_wrist_and_turns_the_swivel_by_as_much() -> None:
    """On clear random postures: the turned posture's wrist stays (within the
    IK's tolerance, else None), the upper arm keeps its length, and the
    elbow's swivel angle (paper eq. 17) changes by the swivel asked."""
    arm = load_arm("right")
    rng = np.random.default_rng(2)
    checked = 0
    for _ in range(40):
        q = clear_posture(arm, rng, inset=0.2)[None, :]
        turned = turn_elbow(arm, q, np.array([0.3]), None)
        if turned is None:  # a joint range stops it: the wrist would move
            continue
        checked += 1
        before, after = key_points(arm, q), key_points(arm, turned.positions)
        assert np.linalg.norm(after["wrist"] - before["wrist"]) < 1e-4
        upper = [np.linalg.norm(p["elbow"] - p["shoulder"]) for p in (before, after)]
        assert upper[0] == pytest.approx(upper[1], abs=1e-9)
        swivels = [
            swivel_angle(p["shoulder"][0], p["elbow"][0], p["wrist"][0])
            for p in (before, after)
        ]
        assert math.remainder(swivels[1] - swivels[0] - 0.3, 2 * math.pi) == (
            pytest.approx(0.0, abs=1e-3)
        )
        assert turned.positions[0, 4] == q[0, 4]  # no palm: WristYaw stays
    assert checked >= 20


def test_a_wanted_palm_keeps_its_roll_through_the_turn() -> None:
    arm = load_arm("right")
    rng = np.random.default_rng(4)
    palm = np.array([0.0, 0.0, 1.0])
    kept = 0
    for _ in range(40):
        q = clear_posture(arm, rng, inset=0.3)[None, :]
        turned = turn_elbow(arm, q, np.array([-0.25]), palm)
        if turned is None:
            continue
        kept += 1
        rolls = [
            roll_error(arm.rotation(p, "wrist"), arm.side.sign, palm)
            for p in (q[0], turned.positions[0])
        ]
        assert math.remainder(rolls[1] - rolls[0], 2 * math.pi) == pytest.approx(
            0.0, abs=1e-9
        )
    assert kept >= 15


def test_a_path_already_clear_is_returned_as_it_was() -> None:
    """A reach from rest to a grid-like point: clear, so the very same path
    comes back and nothing was tried."""
    arm = load_arm("right")
    start = arm.limits.clip(np.array([1.4, -0.2, 1.2, 0.5, 0.0]))
    path = reach_wrist_path(arm, start, ReachTarget(position=(0.12, -0.10, 0.05)))
    joint_path, _ = track_movement(LocalStages(), path, start, Method.MP, None)
    kept = keep_clear(arm, joint_path, None, Method.MP)
    assert kept.path is joint_path and not kept.tried


def _near_head() -> tuple:
    """The stages' joint path of test_planner_body's NEAR_HEAD reach."""
    arm = load_arm("right")
    start = np.array([1.733, -0.603, -1.809, 0.562, 0.09])
    target = ReachTarget(position=(0.0794, -0.0986, 0.1966))
    path = reach_wrist_path(arm, start, target)
    joint_path, _ = track_movement(LocalStages(), path, start, Method.MP, None)
    return arm, joint_path


def test_only_the_turned_samples_are_relabelled() -> None:
    """The tracked path labelled S_R E_P W_P throughout: after the turn, the
    samples the swivel moved say the full primitive (every joint moves
    there) and the others keep their label."""
    arm, joint_path = _near_head()
    labelled = joint_path.model_copy(
        update={"primitives": ["S_R E_P W_P"] * len(joint_path.times)}
    )
    kept = keep_clear(arm, labelled, None, Method.MP)
    assert kept.tried and kept.path is not labelled
    moved = (
        np.abs(np.array(kept.path.positions) - np.array(labelled.positions)).max(axis=1)
        > 0.0
    )
    labels = np.array(kept.path.primitives)
    assert moved.any() and not moved.all()
    assert set(labels[moved]) == {"S_R E_PR W_P"}
    assert set(labels[~moved]) <= {"S_R E_PR W_P", "S_R E_P W_P"}
    assert labels[0] == "S_R E_P W_P"


@pytest.mark.parametrize("tilt", [2.0, 5.0, 10.0])
def test_a_palm_near_the_forearm_axis_does_not_swing_the_wrist(tilt: float) -> None:
    """A palm a few degrees off the forearm's axis, where its roll swings
    with the swivel: a turned path never steps a joint further than STEP (or
    than the tracked path did). WristYaw jumped 2.4 rad in one step at 2
    degrees, before the steps were checked and the roll unwrapped."""
    arm = load_arm("right")
    rng = np.random.default_rng(7)
    for _ in range(115):  # the 115th reach of this draw comes near the body
        start, goal = clear_posture(arm, rng), arm.fk(clear_posture(arm, rng)).wrist
    path = reach_wrist_path(arm, start, ReachTarget(position=tuple(goal)))
    joint_path, _ = track_movement(LocalStages(), path, start, Method.MP, None)
    q = np.array(joint_path.positions)
    assert least_clearances(arm, q).min() < MARGIN
    axis = np.asarray(arm.rotation(q[np.argmin(least_clearances(arm, q))], "wrist"))[
        :, 0
    ]
    across = np.cross(axis, [0.0, 0.0, 1.0])
    across /= np.linalg.norm(across)
    palm = axis * math.cos(math.radians(tilt)) + across * math.sin(math.radians(tilt))
    kept = keep_clear(arm, joint_path, tuple(palm), Method.MP)
    turned = np.array(kept.path.positions)
    own = np.abs(np.diff(q, axis=0)).max()
    assert np.abs(np.diff(turned, axis=0)).max() <= max(STEP, own) + 1e-12
    if kept.path is not joint_path:
        assert least_clearances(arm, turned).min() >= MARGIN
