"""Timing by a caller's path parameter: the hand's arc length gives a human bell."""

from __future__ import annotations

import numpy as np
import pytest
from test_timing_paths import distance_to_polyline

from services.ik.track import track_path
from services.planner.wrist_path import reach_path
from services.timing import check_limits, reach_duration, time_path
from services.timing.parameter_limits import parameter_limits
from services.timing.path_spline import PathSpline
from services.timing.scalar_profile import plan_rest_to_rest
from services.timing.time_path import distinct_points, knot_widths, required_stretch
from shared.errors import InvalidInputError
from shared.primitives import FULL_REACH
from shared.robot import load_arm, motion_limits
from shared.robot.postures import rest

ARM = load_arm("right")
LIMITS = motion_limits(ARM.limits)


def _reach(goal: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """IK joint path of a reach and the hand's arc length along it."""
    path = reach_path(ARM, rest("right"), np.array(goal), 1.0)
    tracked = track_path(ARM, path.positions, rest("right"), lambda k, st: FULL_REACH)
    steps = np.linalg.norm(np.diff(tracked.wrist, axis=0), axis=1)
    return tracked.q, np.concatenate(([0.0], np.cumsum(steps)))


def test_hand_arc_length_gives_a_minimum_jerk_hand_speed() -> None:
    """At the human duration the hand's speed is a bell within 3 % (RMS of the
    peak) of the minimum-jerk profile, peaking mid-movement."""
    q, arc = _reach((0.12, -0.13, 0.05))
    duration = reach_duration(ARM, q[0], q[-1])
    out = time_path(q, LIMITS, duration=duration, parameter=arc)
    assert out.duration == pytest.approx(duration, abs=0.011)
    check_limits(out.times, out.positions, LIMITS)
    hand = np.array([ARM.fk(p).wrist for p in out.positions])
    speed = np.linalg.norm(np.diff(hand, axis=0), axis=1) / np.diff(out.times)
    tau = (np.arange(len(speed)) + 0.5) / len(speed)
    ideal = 30 * tau**2 * (1 - tau) ** 2
    ideal *= speed.sum() / ideal.sum()
    assert np.sqrt(np.mean((speed - ideal) ** 2)) < 0.03 * speed.max()
    assert 0.4 < tau[np.argmax(speed)] < 0.6


def test_the_parameter_does_not_bend_the_path() -> None:
    """Timed by arc length, the samples still pass through the path's ends and
    the hand stays within 1 mm of the IK wrist path."""
    q, arc = _reach((0.12, -0.13, 0.05))
    out = time_path(q, LIMITS, parameter=arc)
    assert np.array_equal(out.positions[0], q[0])
    assert np.allclose(out.positions[-1], q[-1], atol=1e-12)
    ik_wrist = np.array([ARM.fk(p).wrist for p in q])
    timed_wrist = np.array([ARM.fk(p).wrist for p in out.positions])
    assert distance_to_polyline(timed_wrist, ik_wrist).max() < 1e-3


@pytest.mark.parametrize(
    "parameter,message",
    [
        (np.zeros(5), "shape"),
        (np.array([0.0, 1.0, np.nan, 3.0, 4.0, 5.0]), r"parameter\[2\]"),
        (np.array([0.0, 1.0, 0.5, 3.0, 4.0, 5.0]), "decreases at point 2"),
    ],
)
def test_bad_parameters_are_named(parameter: np.ndarray, message: str) -> None:
    """A parameter of the wrong shape, non-finite or decreasing is refused."""
    q = np.linspace(ARM.limits.middle, ARM.limits.middle + 0.3, 6)
    with pytest.raises(InvalidInputError, match=message):
        time_path(q, LIMITS, parameter=parameter)


@pytest.mark.parametrize("points", [2, 11])
def test_a_turn_in_place_is_timed_by_the_joints(points: int) -> None:
    """Only WristYaw turns, so the hand's arc length stands still: timed as
    with no parameter (it gave NaN widths: an untyped error, or a singular
    spline), within the limits, ending at the turn's end."""
    q = np.tile(rest("right"), (points, 1))
    q[:, 4] = np.linspace(0.0, 1.0, points)
    held = time_path(q, LIMITS, parameter=np.zeros(points))
    free = time_path(q, LIMITS)
    assert held.duration == pytest.approx(free.duration)
    check_limits(held.times, held.positions, LIMITS)
    np.testing.assert_allclose(held.positions[-1], q[-1], atol=1e-12)


def test_a_profile_to_be_shrunk_is_judged_alike_on_its_shrunk_grid() -> None:
    """The time-optimal profile under the hand's constant limits on u is too
    slow for the reach (15 s); judged on the grid of the shrunk profile
    (fewer points) its stretch agrees with the full grid's within 1 %, and
    the fastest timing keeps every limit."""
    q, arc = _reach((0.12, -0.13, 0.05))
    points, index = distinct_points(q)
    spline = PathSpline(
        points, knot_widths(points, arc[index], LIMITS), LIMITS.lower, LIMITS.upper
    )
    shape = parameter_limits(spline.bounds(), LIMITS, spline.length)
    profile = plan_rest_to_rest(spline.length, shape)
    full = required_stretch(spline, profile, LIMITS, 0.01)
    shrunk = required_stretch(spline, profile, LIMITS, 0.01, shrunk_grid=True)
    assert profile.duration > 5.0 and full < 1.0  # to be shrunk
    assert shrunk == pytest.approx(full, rel=0.01)
    fastest = time_path(q, LIMITS, parameter=arc)
    check_limits(fastest.times, fastest.positions, LIMITS)
