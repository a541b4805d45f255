"""NAO's body as the arm keeps clear of it: the distance between segments,
checked by a second method and by its identities, and the body model on
postures and targets whose answer is known from the shapes alone."""

from __future__ import annotations

import numpy as np
import pytest

from shared.errors import (
    ArmplanError,
    BodyCollisionError,
    TargetInBodyError,
    UnreachableTargetError,
    error_from_wire,
)
from shared.geometry.segments import segment_distance
from shared.robot import load_arm
from shared.robot.body import (
    HAND,
    MARGIN,
    arm_points,
    check_postures_clear,
    check_target_clear,
    clearances,
    closest,
    first_near,
    first_point_near,
    point_clearance,
)
from shared.robot.fk_many import ONE_BY_ONE, key_points
from shared.robot.postures import forward, mirror, rest


def sampled_distance(p0, p1, q0, q1, n: int = 2001) -> float:
    """The least distance between ``n`` points on each segment [m]."""
    s = np.linspace(0.0, 1.0, n)[:, None]
    a = p0 + s * (p1 - p0)
    # the nearest point of the second to each point of the first: exactly,
    # its projection clamped to the segment; the grid searches the first
    d = q1 - q0
    length = float(d @ d)
    t = np.zeros(n) if length == 0 else np.clip((a - q0) @ d / length, 0.0, 1.0)
    nearest = q0 + t[:, None] * d
    return float(np.linalg.norm(a - nearest, axis=1).min())


def random_segments(rng: np.random.Generator, count: int) -> np.ndarray:
    """Pairs of segments, some short, some parallel, some points (count, 4, 3)."""
    ends = rng.normal(scale=0.1, size=(count, 4, 3))
    ends[::7, 1] = ends[::7, 0]  # a point and a segment
    ends[::11, 3] = ends[::11, 2]
    ends[::13, 3] = ends[::13, 2] + (ends[::13, 1] - ends[::13, 0]) * 0.7  # parallel
    ends[::17, 1] = ends[::17, 0]
    ends[::17, 3] = ends[::17, 2]  # two points
    return ends


def test_the_distance_agrees_with_a_dense_search_along_one_segment() -> None:
    """The closed form against the least distance from 2001 points of the
    first segment to the second: the search can only find more, and at most
    half a step of the first segment more (the distance is 1-Lipschitz)."""
    rng = np.random.default_rng(7)
    ends = random_segments(rng, 400)
    exact = segment_distance(ends[:, 0], ends[:, 1], ends[:, 2], ends[:, 3])
    for k, (p0, p1, q0, q1) in enumerate(ends):
        searched = sampled_distance(p0, p1, q0, q1)
        step = float(np.linalg.norm(p1 - p0)) / 2000
        assert exact[k] <= searched + 1e-12, k
        assert searched - exact[k] <= step / 2 + 1e-12, k


def test_the_distance_is_symmetric_and_ignores_a_rigid_motion() -> None:
    rng = np.random.default_rng(8)
    ends = random_segments(rng, 200)
    d = segment_distance(ends[:, 0], ends[:, 1], ends[:, 2], ends[:, 3])
    swapped = segment_distance(ends[:, 2], ends[:, 3], ends[:, 0], ends[:, 1])
    reversed_ = segment_distance(ends[:, 1], ends[:, 0], ends[:, 3], ends[:, 2])
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    moved = ends @ rotation.T + np.array([0.3, -0.2, 0.5])
    turned = segment_distance(moved[:, 0], moved[:, 1], moved[:, 2], moved[:, 3])
    np.testing.assert_allclose(swapped, d, atol=1e-12)
    np.testing.assert_allclose(reversed_, d, atol=1e-12)
    np.testing.assert_allclose(turned, d, atol=1e-12)


@pytest.mark.parametrize(
    ("p0", "p1", "q0", "q1", "expected"),
    [
        # crossing lines 0.1 apart, closest points inside both segments
        ((-1, 0, 0), (1, 0, 0), (0, -1, 0.1), (0, 1, 0.1), 0.1),
        # parallel, overlapping: the gap between the lines
        ((0, 0, 0), (1, 0, 0), (0.5, 0.3, 0), (2, 0.3, 0), 0.3),
        # collinear, apart: end to end
        ((0, 0, 0), (1, 0, 0), (1.5, 0, 0), (2, 0, 0), 0.5),
        # a point beside a segment's middle, and beyond its end
        ((0, 0, 0), (1, 0, 0), (0.5, 0.2, 0), (0.5, 0.2, 0), 0.2),
        ((0, 0, 0), (1, 0, 0), (1.3, 0.4, 0), (1.3, 0.4, 0), 0.5),
        # two points
        ((0, 0, 0), (0, 0, 0), (0, 3, 4), (0, 3, 4), 5.0),
    ],
)
def test_distances_known_from_the_figure(p0, p1, q0, q1, expected) -> None:
    assert segment_distance(p0, p1, q0, q1) == pytest.approx(expected, abs=1e-12)


def test_the_arm_hanging_or_stretched_forward_keeps_clear() -> None:
    """Rest and the handover's start keep more than the margin; the left
    arm's mirror postures keep the same distances (the body is symmetric
    about the sagittal plane)."""
    right, left = load_arm("right"), load_arm("left")
    for posture in (rest("right"), forward("right")):
        near = closest(right, [posture])
        assert near.clearance > 4 * MARGIN
        mirrored = clearances(arm_points(left, [mirror(posture)]))
        np.testing.assert_allclose(
            mirrored, clearances(arm_points(right, [posture])), atol=1e-12
        )


def test_a_forearm_folded_across_the_chest_is_inside_the_torso() -> None:
    """ShoulderPitch 0, the arm forward and rolled in, the elbow bent fully
    sideways: the hand comes back across the chest, into the torso capsule
    (radius 55 mm about the z axis, x = 0)."""
    arm = load_arm("right")
    posture = np.array([0.0, 0.3, 0.0, 1.54, 0.0])
    points = arm_points(arm, [posture])
    assert points["hand"][0, 0] < 0.055 + HAND  # the hand's side at the chest
    near = closest(arm, [posture])
    assert near.body_part == "torso"
    assert near.clearance < 0
    with pytest.raises(
        BodyCollisionError, match=r"torso at sample 1 \(t = 0\.020 s\)"
    ) as err:
        check_postures_clear(arm, [rest("right"), posture], [0.0, 0.02])
    assert err.value.index == 1
    assert err.value.clearance == pytest.approx(near.clearance)


def test_the_first_posture_too_near_is_named_not_the_deepest() -> None:
    arm = load_arm("right")
    folded = np.array([0.0, 0.3, 0.0, 1.54, 0.0])
    less = np.array([0.0, 0.3, 0.0, 1.5, 0.0])
    depths = [closest(arm, [q]).clearance for q in (less, folded)]
    assert MARGIN > depths[0] > depths[1]
    near = first_near(arm, [rest("right"), less, folded])
    assert near is not None and near.sample == 1
    assert first_near(arm, [rest("right"), forward("right")]) is None


@pytest.mark.parametrize(
    ("target", "part", "words"),
    [
        ((0.03, 0.0, 0.02), "torso", "is inside NAO's torso"),
        ((0.03, -0.03, 0.0), "torso", "is too near NAO's torso"),  # 3 mm out
        ((0.0, -0.03, 0.22), "head", "is inside NAO's head"),
        ((0.0, -0.05, 0.25), "head", "is too near NAO's head"),
        ((0.0, -0.02, -0.03), "pelvis", "is inside NAO's pelvis"),
        ((0.0, -0.04, -0.04), "pelvis", "is too near NAO's pelvis"),
    ],
)
def test_a_target_in_the_body_is_refused_as_out_of_reach(target, part, words) -> None:
    """Within the arm's reach shell; "inside" only when the point itself is
    in the part, "too near" when only the hand's ball would be."""
    arm = load_arm("right")
    with pytest.raises(TargetInBodyError, match=words) as err:
        check_target_clear(arm, target)
    assert isinstance(err.value, UnreachableTargetError)
    assert err.value.body_part == part
    assert err.value.clearance < 0
    assert err.value.inside == ("inside" in words)
    # the hand's ball at the target: its clearance is the shapes' alone
    assert err.value.clearance == pytest.approx(point_clearance(target, HAND)[1])
    assert arm.reach[0] < np.linalg.norm(np.subtract(target, (0, -0.098, 0.1)))


def test_a_target_just_outside_the_margin_passes_and_just_inside_is_refused() -> None:
    """Straight ahead of the chest at z = 55 mm: the torso's surface is at
    x = 55 mm, so the hand's ball (30 mm) keeps the margin from x = 90 mm
    + MARGIN on."""
    arm = load_arm("right")
    edge = 0.055 + HAND + MARGIN
    check_target_clear(arm, (edge + 1e-4, 0.0, 0.055))
    with pytest.raises(TargetInBodyError, match=r"nearer than the 5\.0 mm kept"):
        check_target_clear(arm, (edge - 1e-4, 0.0, 0.055))


def test_the_refusals_cross_the_wire_as_their_kinds() -> None:
    arm = load_arm("left")
    with pytest.raises(TargetInBodyError) as target:
        check_target_clear(arm, (0.0, 0.03, 0.05))
    posture = mirror(np.array([0.0, 0.3, 0.0, 1.54, 0.0]))
    with pytest.raises(BodyCollisionError) as movement:
        check_postures_clear(arm, [posture], [0.5])
    for error in (target.value, movement.value):
        back = error_from_wire(error.to_wire())
        assert type(back) is type(error)
        assert isinstance(back, ArmplanError)
        assert back.evidence == error.evidence
    assert isinstance(error_from_wire(target.value.to_wire()), UnreachableTargetError)
    assert movement.value.arm == "left"


@pytest.mark.parametrize("side", ["right", "left"])
def test_many_postures_at_once_agree_with_pinocchio_one_at_a_time(side: str) -> None:
    """``key_points`` composes the chain in numpy for all postures; pinocchio's
    ``fk`` gives each posture's points: the two agree to round-off."""
    arm = load_arm(side)
    rng = np.random.default_rng(21)
    q = rng.uniform(arm.limits.lower, arm.limits.upper, size=(300, 5))
    points = key_points(arm, q)
    for name in ("shoulder", "elbow", "wrist", "hand"):
        one_by_one = np.array([getattr(arm.fk(posture), name) for posture in q])
        np.testing.assert_allclose(points[name], one_by_one, rtol=0, atol=1e-12)
    for few in range(ONE_BY_ONE + 1):  # pinocchio's answers below, numpy's at
        some = key_points(arm, q[:few])
        for name in ("shoulder", "elbow", "wrist", "hand"):
            assert some[name].shape == (few, 3)
            np.testing.assert_allclose(some[name], points[name][:few], atol=1e-12)
    single = key_points(arm, q[0])
    assert single["hand"].shape == (1, 3)


def test_a_posture_that_is_no_number_counts_as_near() -> None:
    """NaN compares false with everything: were it taken as clear, a NaN
    posture from anywhere would pass every check."""
    arm = load_arm("right")
    nan = np.array([np.nan, 0.0, 0.0, 0.5, 0.0])
    near = first_near(arm, [rest("right"), nan])
    assert near is not None and near.sample == 1
    assert first_point_near([[0.15, -0.1, 0.05], [np.nan, 0.0, 0.0]]) == 1
    with pytest.raises(TargetInBodyError):
        check_target_clear(arm, (np.nan, 0.0, 0.0))
