"""The stretch holds the jerk limit on the whole timed curve, knots included.

The joints' jerk steps at every knot of the C2 path spline and at every
phase boundary of Ruckig's profile; judged on an even grid alone, the stretch
missed the steps between its points (up to 5 times the limit just past a
knot), and the samples then changed acceleration faster than the limit.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from services.planner.build import arc_length
from services.planner.pipeline import plan, track_movement
from services.planner.reach_path import reach_wrist_path
from services.planner.stages import LocalStages
from services.timing.path_spline import PathSpline
from services.timing.time_path import distinct_points, fit_profile, knot_widths
from shared.messages import PlanRequest
from shared.robot import load_arm, motion_limits
from shared.robot.postures import rest

ARM = load_arm("right")
LIMITS = motion_limits(ARM.limits)
#: The left-arm task's targets, torso frame [m].
LEFT_HIGH = (-0.03293450829780795, 0.19962933629072827, 0.19576830069871876)
LEFT_OPEN = (0.06431162343526244, 0.21850674588912233, 0.10406721736704176)
LEFT_LOW = (-0.027759228095417136, 0.20519536330560825, 0.03397335391528005)
LEFT_FAR = (0.15688921975629125, 0.07390096080506527, 0.10780728246436942)
LEFT_BACK = (-0.06511609344698654, 0.16983485253280128, 0.1655981158817577)
#: Time step of the dense check [s], 1/1000 of a sample period.
DENSE = 1e-5


def _spline(goal: tuple[float, float, float]) -> PathSpline:
    """The path spline of the reach from rest to ``goal`` the planner's stages
    track, by the hand's arc length. (The planner itself refuses the third
    goal's plan now: the hand passes within 5 mm of NAO's head.)"""
    request = PlanRequest.model_validate(
        {"arm": "right", "targets": [{"position": goal}]}
    )
    start = rest("right")
    wrist = reach_wrist_path(load_arm("right"), start, request.targets[0])
    path, _ = track_movement(LocalStages(), wrist, start, request.method, None)
    points, index = distinct_points(np.array(path.positions))
    widths = knot_widths(points, arc_length(path.wrist)[index], LIMITS)
    return PathSpline(points, widths, LIMITS.lower, LIMITS.upper)


@pytest.mark.parametrize(
    "goal", [(0.12, -0.10, 0.05), (0.12, -0.13, 0.05), (0.10, -0.05, 0.15)]
)
@pytest.mark.parametrize("duration", [None, 0.5])
def test_the_jerk_keeps_its_limit_between_the_stretch_points(
    goal: tuple[float, float, float], duration: float | None
) -> None:
    """Fastest and a short human bell: the chain-rule jerk of q(u(t)) every
    10 us keeps the limit (it was 1.02 times it on the first two reaches,
    1.001 times on the third)."""
    spline = _spline(goal)
    profile = fit_profile(spline, LIMITS, duration, 0.01)
    u = profile.sample(np.arange(0.0, profile.duration, DENSE))
    s = spline.evaluate(u.position)
    ud, udd, uddd = u.velocity[:, None], u.acceleration[:, None], u.jerk[:, None]
    jerk = s.third * ud**3 + 3.0 * s.second * ud * udd + s.first * uddd
    assert np.max(np.abs(jerk) / LIMITS.jerk) <= 1.0 + 1e-9


def test_the_samples_change_acceleration_within_the_jerk_limit() -> None:
    """A five-target left-arm task, fastest: LElbowYaw's acceleration went
    from 0.08 to -7.78 rad/s^2 in one 10 ms step, 1.19 times the jerk
    limit, just past a knot the stretch did not look at."""
    targets = [
        {"position": LEFT_HIGH},
        {"position": LEFT_OPEN, "hand": "open"},
        {"position": LEFT_LOW, "dwell": 0.8365495668997975},
        {"position": LEFT_FAR, "dwell": 0.5514770349284381},
        {"position": LEFT_BACK, "dwell": 0.3692700139303806},
    ]
    task = {"arm": "left", "targets": targets, "method": "single", "fastest": True}
    trajectory = plan(PlanRequest.model_validate_json(json.dumps(task))).trajectory
    limits = motion_limits(load_arm("left").limits)
    steps = np.diff(trajectory.times)[:, None]
    jerk = np.diff(np.array(trajectory.accelerations), axis=0) / steps
    assert np.max(np.abs(jerk) / limits.jerk) <= 1.0 + 1e-9
