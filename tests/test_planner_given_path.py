"""A timed wrist path is a contract: followed within a tolerance, or refused."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from services.ik import check_reachable
from services.planner.even_path import even_grid
from services.planner.pipeline import GIVEN_PATH_ADVICE, PATH_TOLERANCE, plan
from services.planner.wrist_path import reach_path
from shared.errors import (
    BodyCollisionError,
    InvalidInputError,
    LimitViolationError,
    OffPathError,
    UnreachableTargetError,
)
from shared.messages import Method, PlanRequest, WristPath, parse
from shared.robot import ArmModel, load_arm
from shared.robot.body import MARGIN, first_near
from shared.robot.postures import rest


def _minimum_jerk(u: np.ndarray) -> np.ndarray:
    return u**3 * (10.0 - 15.0 * u + 6.0 * u * u)


def joint_motion_path(
    arm: ArmModel, seed: int, times: np.ndarray
) -> tuple[WristPath, np.ndarray]:
    """The wrist of a minimum-jerk joint motion between two random postures
    (seeded, 0.1 rad inside the ranges) at ``times``: a path that postures
    within the limits follow exactly. The first draw whose straight way in
    joint space keeps twice the margin from NAO's body (``shared.robot.body``)
    is taken. Returns the path and the start posture."""
    rng = np.random.default_rng(seed)
    lower, upper = arm.limits.lower + 0.1, arm.limits.upper - 0.1
    way = np.linspace(0.0, 1.0, 201)[:, None]
    while True:
        q0, q1 = rng.uniform(lower, upper), rng.uniform(lower, upper)
        if first_near(arm, q0 + way * (q1 - q0), 2 * MARGIN) is None:
            break
    u = (times - times[0]) / (times[-1] - times[0])
    q = q0 + np.outer(_minimum_jerk(u), q1 - q0)
    wrists = [tuple(arm.fk(p).wrist.tolist()) for p in q]
    return WristPath(arm=arm.side, times=times.tolist(), positions=wrists), q0


def _wrist_errors(arm: ArmModel, path: WristPath, q: list[list[float]]) -> np.ndarray:
    wrists = np.array([arm.fk(np.array(p)).wrist for p in q])
    return np.linalg.norm(wrists - np.array(path.positions), axis=1)


def test_a_path_the_tracker_leaves_is_refused_naming_the_sample() -> None:
    """Method single from this start leaves the path by 4 cm (it went on as
    a joint-space detour and answered with exit 0): refused, naming the
    sample farthest off, its time and the distance."""
    arm = load_arm("right")
    path, start = joint_motion_path(arm, 40, np.linspace(0.0, 4.0, 401))
    request = PlanRequest(
        arm=arm.side, wrist_path=path, method=Method.SINGLE, start=tuple(start)
    )
    with pytest.raises(OffPathError) as caught:
        plan(request)
    error = caught.value
    assert error.deviation > 0.03
    assert error.tolerance == PATH_TOLERANCE
    assert error.time == path.times[error.index]
    assert f"sample {error.index} (t = {error.time:.3f} s)" in error.message
    assert f"{error.deviation * 1000:.2f} mm from the path" in error.message


def test_a_looser_tolerance_takes_the_same_path() -> None:
    arm = load_arm("right")
    path, start = joint_motion_path(arm, 40, np.linspace(0.0, 4.0, 401))
    result = plan(
        PlanRequest(
            arm=arm.side,
            wrist_path=path,
            method=Method.SINGLE,
            start=tuple(start),
            path_tolerance=0.1,
        )
    )
    assert _wrist_errors(arm, path, result.trajectory.positions).max() <= 0.1


@pytest.mark.parametrize("method", list(Method))
def test_a_followed_path_stays_within_the_tolerance(method: Method) -> None:
    arm = load_arm("left")
    path, start = joint_motion_path(arm, 3, np.linspace(0.0, 4.0, 101))
    result = plan(
        PlanRequest(arm=arm.side, wrist_path=path, method=method, start=tuple(start))
    )
    assert _wrist_errors(arm, path, result.trajectory.positions).max() < 1e-4


@pytest.mark.parametrize("method", list(Method))
def test_a_few_waypoints_a_second_are_followed(method: Method) -> None:
    """Eight even waypoints over 5 s (seeded joint motions, both arms): each
    is followed, the wrist on every waypoint. (Tracked one step per waypoint,
    55 of these 60 plans were refused, the wrist millimetres off.) The
    method's postures are not the motion's: one that brings the arm near
    NAO's body is refused, and left out here."""
    followed = 0
    for seed in range(10):
        arm = load_arm("left" if seed % 2 else "right")
        path, start = joint_motion_path(arm, 900 + seed, np.linspace(0.0, 5.0, 8))
        request = PlanRequest(
            arm=arm.side, wrist_path=path, method=method, start=tuple(start)
        )
        try:
            result = plan(request)
        except BodyCollisionError:
            continue
        followed += 1
        assert result.trajectory.times == path.times
        assert _wrist_errors(arm, path, result.trajectory.positions).max() < 1e-4
    assert followed >= 8


def test_a_tolerance_belongs_to_a_wrist_path() -> None:
    with pytest.raises(InvalidInputError, match="path_tolerance"):
        parse(
            PlanRequest,
            {"targets": [{"position": [0.12, -0.1, 0.05]}], "path_tolerance": 0.01},
        )
    plain = parse(PlanRequest, {"targets": [{"position": [0.12, -0.1, 0.05]}]})
    assert "path_tolerance" not in plain.to_json()  # the JSON as before


def test_the_joints_do_not_depend_on_where_the_path_was_sampled() -> None:
    """The planner's 2 s reach at 100 Hz with 30 % of its samples dropped
    (seeded): accepted, the joints at the kept times within 5 mrad of the
    full path's, the wrist on the path. (Tracked by its points, one step
    each, the gappy path's joints differed by 0.1 rad and their jerk broke
    the limit where the full path used 0.04 of it.)"""
    arm = load_arm("right")
    reach = reach_path(arm, rest(arm.side), np.array([0.12, -0.13, 0.05]), 2.0)
    full = WristPath(
        arm=arm.side,
        times=(3.0 * reach.times).tolist(),
        positions=[tuple(p) for p in reach.positions.tolist()],
    )
    keep = np.random.default_rng(1).random(len(full.times)) > 0.3
    keep[[0, -1]] = True
    gappy = WristPath(
        arm=arm.side,
        times=[t for t, k in zip(full.times, keep, strict=True) if k],
        positions=[p for p, k in zip(full.positions, keep, strict=True) if k],
    )
    whole = plan(PlanRequest(arm=arm.side, wrist_path=full)).trajectory
    part = plan(PlanRequest(arm=arm.side, wrist_path=gappy)).trajectory
    assert part.times == gappy.times
    at_kept = np.array(whole.positions)[keep]
    assert np.abs(np.array(part.positions) - at_kept).max() < 5e-3
    assert _wrist_errors(arm, gappy, part.positions).max() < 1e-4


def test_a_dense_path_is_tracked_on_the_planners_grid() -> None:
    """The planner's reach done in 1 s, sampled every 5 ms: accepted, and
    its joints at the 10 ms samples within 5 mrad of the same path sampled
    every 10 ms. (Tracked one step per 5 ms sample, the blend and null-space
    steps came twice as fast: refused, RElbowYaw acceleration 38.6 > 33.1.)"""
    arm = load_arm("right")
    reach = reach_path(arm, rest(arm.side), np.array([0.12, -0.13, 0.05]), 2.0)
    dense = WristPath(
        arm=arm.side,
        times=(0.5 * reach.times).tolist(),
        positions=[tuple(p) for p in reach.positions.tolist()],
    )
    every_10_ms = WristPath(
        arm=arm.side, times=dense.times[::2], positions=dense.positions[::2]
    )
    part = plan(PlanRequest(arm=arm.side, wrist_path=dense)).trajectory
    whole = plan(PlanRequest(arm=arm.side, wrist_path=every_10_ms)).trajectory
    assert part.times == dense.times
    gap = np.array(part.positions)[::2] - np.array(whole.positions)
    assert np.abs(gap).max() < 5e-3
    assert _wrist_errors(arm, dense, part.positions).max() < 1e-4


def _resampled(path: WristPath, step: float, slower: float) -> WristPath:
    """``path`` slowed ``slower`` times, every ``step`` [s] on its clamped spline."""
    times = slower * np.asarray(path.times)
    grid = np.round(np.arange(0.0, times[-1] + 1e-9, step), 9)
    grid[-1] = times[-1]
    spline = CubicSpline(times, np.asarray(path.positions), bc_type="clamped")
    positions = [tuple(p) for p in spline(grid).tolist()]
    return WristPath(arm=path.arm, times=grid.tolist(), positions=positions)


def test_the_jerk_check_does_not_depend_on_the_sampling() -> None:
    """The planner's own 0.64 s reach path at its own times plays RElbowYaw
    jerk 689 rad/s^3 between samples 42 and 43 (limit 661): refused,
    sampled every 10 ms or every 5 ms, for the same jerk at the same time;
    1.5 times slower, accepted at both. (The 10 ms path was accepted, its
    samples reading the jerk averaged over three pieces; wrist curves like
    it were refused at 5 ms and accepted at 10 ms.)"""
    own = plan(PlanRequest(targets=[{"position": (0.12, -0.13, 0.05)}]))
    path = own.wrist_paths[0]
    begin = tuple(rest("right"))
    refusals = []
    for step in (0.01, 0.005):
        with pytest.raises(LimitViolationError) as caught:
            plan(PlanRequest(wrist_path=_resampled(path, step, 1.0), start=begin))
        refusals.append(caught.value)
    for error in refusals:
        assert (error.joint, error.quantity) == ("RElbowYaw", "jerk")
        assert error.value > error.limit
        assert "on the curve between samples" in error.message
        assert error.advice == GIVEN_PATH_ADVICE  # what to do, not only what broke
        assert error.message.endswith("raise limits.jerk / limits.acceleration")
    assert refusals[0].time == pytest.approx(refusals[1].time, abs=0.011)
    assert refusals[0].value == pytest.approx(refusals[1].value, rel=0.05)
    for step in (0.01, 0.005):
        slower = _resampled(path, step, 1.5)
        assert plan(PlanRequest(wrist_path=slower, start=begin)).trajectory.times == (
            slower.times
        )


@pytest.mark.parametrize("nudge", [0.001, 0.004, 0.008])
def test_a_start_a_little_off_the_path_starts_on_it(nudge: float) -> None:
    """A start posture whose wrist is 0.1-0.8 mm from the path's first
    sample: the trajectory starts on the sample. (Kept as the first posture,
    the tracker closed the gap in one step: refused, jerk 957 > 661.)"""
    arm = load_arm("right")
    path, start = joint_motion_path(arm, 3, np.linspace(0.0, 4.0, 401))
    nudged = start + np.array([nudge, 0.0, 0.0, 0.0, 0.0])
    off = np.linalg.norm(arm.fk(nudged).wrist - np.array(path.positions[0]))
    assert 5e-5 < off < 1e-3
    result = plan(PlanRequest(arm=arm.side, wrist_path=path, start=tuple(nudged)))
    assert _wrist_errors(arm, path, result.trajectory.positions).max() < 1e-5


def leaving_the_reach(arm: ArmModel) -> WristPath:
    """Four samples within reach whose clamped spline leaves it (below)."""
    hanging = arm.fk(rest(arm.side))
    way = np.array([1.0, -0.3, 0.3]) / np.linalg.norm([1.0, -0.3, 0.3])
    far = hanging.shoulder + way * arm.reach[1] * 0.97
    samples = [hanging.wrist, far, far, hanging.wrist]
    times = [0.0, 1.0, 1.15, 2.5]
    return WristPath(arm=arm.side, times=times, positions=[tuple(p) for p in samples])


def test_a_sparse_path_whose_curve_leaves_the_reach_names_the_gap() -> None:
    """Four samples within reach at 0, 1.0, 1.15 and 2.5 s (the hanging
    wrist, a point at 0.97 of the reach, held 0.15 s, back): the curve
    through them passes 0.103 m from the shoulder, nearer than the wrist
    can come (0.114 m). Refused as unreachable, naming the two samples the
    curve leaves the reach between and asking for more there. (It was an
    OffPathError, the wrist 176 mm from sample 2, blaming the tracker.)"""
    arm = load_arm("right")
    path = leaving_the_reach(arm)
    times = path.times
    for point in path.positions:
        check_reachable(arm, np.array(point))
    with pytest.raises(UnreachableTargetError) as caught:
        plan(PlanRequest(arm=arm.side, wrist_path=path))
    error = caught.value
    assert not arm.reach[0] <= error.distance <= arm.reach[1]
    gap = re.search(r"between samples (\d) \(t = [\d.]+ s\) and (\d) ", error.message)
    assert gap is not None, error.message
    before, after = int(gap[1]), int(gap[2])
    assert after == before + 1
    at = float(re.search(r"at t = ([\d.]+) s", error.message)[1])  # type: ignore[index]
    assert times[before] < at < times[after]
    assert "add samples between them" in error.message


#: Six noisy, unevenly timed samples of a reach from the hanging wrist [s, m].
NOISY_TIMES = (0.0, 1.484776, 1.973796, 2.610256, 3.541170, 5.034065)
NOISY_SAMPLES = (
    (0.011115549, -0.128881909, -0.057538716),
    (0.039103548, -0.126390845, -0.020585743),
    (0.089306446, -0.107284251, 0.023453304),
    (0.094191655, -0.105186115, 0.020793642),
    (0.096762002, -0.107540872, 0.027968466),
    (0.096762002, -0.107540872, 0.027968466),
)


def _noisy_reach(arm: ArmModel, speed: float) -> WristPath:
    """The noisy reach, ``speed`` times as fast."""
    times = [t / speed for t in NOISY_TIMES]
    return WristPath(arm=arm.side, times=times, positions=list(NOISY_SAMPLES))


def test_a_path_poking_a_hair_out_of_the_reach_between_samples_is_planned() -> None:
    """Six noisy samples from the hanging wrist (0.8 mm inside the reach
    shell), unevenly timed: the curve drawn through them pokes 0.07 mm out
    of the shell between the first two. The grid's reach used to be checked
    before tracking, at the IK's 0.1 mm, and the path was refused though the
    tracker follows it exactly; it is checked only to explain a failure."""
    arm = load_arm("right")
    path = _noisy_reach(arm, 1.0)
    grid = even_grid(path)
    shoulder = arm.fk(rest(arm.side)).shoulder
    farthest = np.linalg.norm(np.asarray(grid.positions) - shoulder, axis=1).max()
    assert farthest > arm.reach[1]  # the drawn curve leaves the shell
    result = plan(PlanRequest(arm=arm.side, wrist_path=path))
    assert _wrist_errors(arm, path, result.trajectory.positions).max() < 1e-5


def test_a_path_too_fast_keeps_its_limit_error_though_its_curve_pokes_out() -> None:
    """The path above 5 times faster, with a path tolerance of 0.05 mm: its
    curve pokes 0.1 mm out of the reach, but what stops it is RShoulderPitch
    acceleration; it was refused as unreachable, "add samples", which would
    not help. It keeps the limit error and its advice."""
    arm = load_arm("right")
    path = _noisy_reach(arm, 5.0)
    with pytest.raises(LimitViolationError) as caught:
        plan(PlanRequest(arm=arm.side, wrist_path=path, path_tolerance=5e-5))
    assert caught.value.quantity == "acceleration"
    assert caught.value.advice == GIVEN_PATH_ADVICE
