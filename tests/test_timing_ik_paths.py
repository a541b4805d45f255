"""Timing real IK joint paths: within every limit, and on the IK's wrist path."""

from __future__ import annotations

import numpy as np
from test_timing_paths import distance_to_polyline, wrists

from services.ik.track import track_path
from services.planner.wrist_path import reach_path
from services.timing import check_limits, reach_duration, time_path
from shared.primitives import FULL_REACH
from shared.robot import ArmModel, motion_limits
from shared.robot.postures import rest

#: Random reachable targets per arm (each IK path costs about 0.1 s).
TARGETS = 12
#: Wrist step between IK points beyond which the IK itself left the path [m].
IK_LEFT_THE_PATH = 0.005


def _ik_path(arm: ArmModel, goal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint path and wrist positions of a 1 s reach from rest to ``goal``, 100 Hz."""
    start = rest(arm.side)
    path = reach_path(arm, start, goal, 1.0)
    tracked = track_path(arm, path.positions, start, lambda k, kin: FULL_REACH)
    return tracked.q, tracked.wrist


def test_ik_reaches_are_within_limits_and_on_the_wrist_path(arm: ArmModel) -> None:
    """Human and fastest timings of IK reaches: limits hold, wrist within 1 mm.

    The 1 mm is checked where the IK path is a path: consecutive IK wrist
    points closer than 5 mm (some IK paths jump by centimetres between two
    points; no interpolation can stay near a polyline there).
    """
    limits = motion_limits(arm.limits)
    rng = np.random.default_rng(0)
    followed = 0
    for _ in range(TARGETS):
        goal = arm.fk(rng.uniform(arm.limits.lower, arm.limits.upper)).wrist
        q, wrist = _ik_path(arm, goal)
        dense = np.linalg.norm(np.diff(wrist, axis=0), axis=1).max() < IK_LEFT_THE_PATH
        followed += dense
        for duration in (reach_duration(arm, q[0], q[-1]), None):
            out = time_path(q, limits, duration=duration)
            check_limits(out.times, out.positions, limits)
            assert np.linalg.norm(arm.fk(out.positions[-1]).wrist - wrist[-1]) < 1e-9
            if dense:
                gap = distance_to_polyline(wrists(arm, out.positions), wrist)
                assert gap.max() < 1e-3
    assert followed >= TARGETS // 2
