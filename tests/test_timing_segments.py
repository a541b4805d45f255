"""Multi-target tasks: segments with rests, and one path with stops."""

from __future__ import annotations

import numpy as np
import pytest
from test_timing_paths import random_smooth_path

from services.timing import Segment, check_limits, time_path_with_stops, time_segments
from shared.errors import InvalidInputError
from shared.robot import load_arm, motion_limits

ARM = load_arm("right")
LIMITS = motion_limits(ARM.limits)
HOME = ARM.limits.middle


def _reach_hold_retreat() -> list[Segment]:
    out = np.linspace(HOME, HOME + np.array([0.5, -0.2, 0.3, 0.4, 0.1]), 50)
    return [Segment(out, 0.8, 0.5), Segment(out[::-1], None, 0.0)]


def test_reach_hold_retreat_is_one_trajectory_within_limits() -> None:
    """The joined trajectory is uniform in time, within limits, and holds still."""
    task = _reach_hold_retreat()
    out = time_segments(task, LIMITS)
    assert np.allclose(np.diff(out.times), 0.01)
    check_limits(out.times, out.positions, LIMITS)
    held = np.flatnonzero(np.all(out.positions == task[0].path[-1], axis=1))  # type: ignore[index]
    assert held.size >= 50  # 0.5 s at 100 Hz (plus the ends of the moves)
    assert np.allclose(out.velocities[held], 0.0, atol=1e-9)
    assert np.allclose(out.positions[[0, -1]], [HOME, HOME])


def test_path_index_counts_along_the_joined_path() -> None:
    """Segment 2's points follow segment 1's, its first point counted once."""
    out = time_segments(_reach_hold_retreat(), LIMITS)
    assert out.path_index[0] == 0 and out.path_index[-1] == 98
    assert np.all(np.diff(out.path_index) >= 0)
    assert 49.0 in out.path_index


def test_a_target_already_reached_is_only_its_dwell() -> None:
    """A still segment between the reach and the retreat (a repeated target):
    no movement time, its dwell added to the rest, rest samples pointing at
    the join (the reach's last point), the same motion otherwise."""
    reach, retreat = _reach_hold_retreat()
    still = Segment(np.tile(reach.path[-1], (31, 1)), 0.5, 0.3)  # type: ignore[index]
    plain = time_segments([reach, retreat], LIMITS)
    out = time_segments([reach, still, retreat], LIMITS)
    assert out.duration == pytest.approx(plain.duration + 0.3)
    check_limits(out.times, out.positions, LIMITS)
    rest = np.isclose(out.path_index, 49.0)
    assert rest.sum() == 80  # 0.8 s at 100 Hz; the last sample starts the retreat
    assert out.path_index[-1] == 49 + 30 + 49


def test_a_task_of_one_target_already_reached_holds() -> None:
    """Nothing to move: the dwell alone, or one sample without one."""
    still = np.tile(HOME, (31, 1))
    assert time_segments([Segment(still, None, 0.2)], LIMITS).duration == 0.2
    single = time_segments([Segment(still, None, 0.0)], LIMITS)
    assert len(single.times) == 1 and np.array_equal(single.positions[0], HOME)


def test_dwell_rounds_up_to_whole_periods() -> None:
    """A 0.123 s dwell holds for 0.13 s at 100 Hz."""
    task = _reach_hold_retreat()
    a = time_segments([task[0]._replace(dwell=0.0), task[1]], LIMITS)
    b = time_segments([task[0]._replace(dwell=0.123), task[1]], LIMITS)
    assert b.duration - a.duration == pytest.approx(0.13)


def test_segments_that_do_not_join_are_refused() -> None:
    """Segment 1 must start where segment 0 ended."""
    task = _reach_hold_retreat()
    broken = [task[0], Segment(task[1].path[1:])]  # type: ignore[index]
    with pytest.raises(InvalidInputError, match=r"segment 1 starts .* away from"):
        time_segments(broken, LIMITS)


@pytest.mark.parametrize("dwell", [-0.1, np.nan])
def test_bad_dwell_is_refused(dwell: float) -> None:
    """Negative or NaN dwells name the segment."""
    task = _reach_hold_retreat()
    with pytest.raises(InvalidInputError, match="dwell of segment 0"):
        time_segments([task[0]._replace(dwell=dwell), task[1]], LIMITS)


def test_no_segments_is_refused() -> None:
    """An empty task is an error, not an empty trajectory."""
    with pytest.raises(InvalidInputError, match="at least one segment"):
        time_segments([], LIMITS)


def test_a_path_stops_where_asked() -> None:
    """At each stop index the arm is at that point with zero speed."""
    path = random_smooth_path(np.random.default_rng(1), LIMITS, 90)
    out = time_path_with_stops(path, LIMITS, [30, 60], dwells=[0.2, 0.0])
    check_limits(out.times, out.positions, LIMITS)
    for stop in (30, 60):
        at = np.flatnonzero(out.path_index == stop)
        assert at.size > 0
        assert np.allclose(out.positions[at], path[stop])
        assert np.allclose(out.velocities[at], 0.0, atol=1e-9)
    assert np.count_nonzero(out.path_index == 30) >= 21


@pytest.mark.parametrize("stops", [[0], [10, 10], [89], [50, 20]])
def test_bad_stops_are_refused(stops: list[int]) -> None:
    """Stops must be inner indices in increasing order."""
    path = random_smooth_path(np.random.default_rng(1), LIMITS, 90)
    with pytest.raises(InvalidInputError, match="stop indices must increase"):
        time_path_with_stops(path, LIMITS, stops)
