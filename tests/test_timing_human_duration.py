"""Human durations: the Table 4 fit, the grid, and NAO's retargeted reaches."""

from __future__ import annotations

import numpy as np
import pytest

from services.timing import paper_grid, reach_duration, time_path
from services.timing.human_duration import (
    DURATION_EXPONENT,
    DURATION_SCALE,
    MIN_DURATION,
    fit_table4,
    human_distance_ratio,
    human_duration,
    human_wrist,
)
from shared.robot import ArmModel, load_arm, motion_limits
from shared.robot.postures import rest


def test_constants_are_the_fit_to_table4() -> None:
    """A fresh least-squares fit gives the stored constants (to 1e-3)."""
    scale, exponent = fit_table4()
    assert scale == pytest.approx(DURATION_SCALE, abs=1e-3)
    assert exponent == pytest.approx(DURATION_EXPONENT, abs=1e-3)


def test_grid_durations_are_in_the_human_range_and_near_table4() -> None:
    """P1..P16: within 0.12 s of Table 4 each, RMS below 0.07 s, 0.5..1.1 s."""
    model = np.array([human_duration(d) for d in paper_grid.grid_distances()])
    table = paper_grid.TABLE4_TIMES
    assert np.all(np.abs(model - table) < 0.12)
    assert np.sqrt(np.mean((model - table) ** 2)) < 0.07
    assert model.min() > 0.5 and model.max() < 1.1


def test_longer_reaches_take_longer_with_a_floor() -> None:
    """Monotone in the distance; never below MIN_DURATION."""
    ratios = np.linspace(0.0, 2.0, 50)
    durations = [human_duration(r) for r in ratios]
    assert np.all(np.diff(durations) >= 0)
    assert min(durations) == MIN_DURATION


def test_nao_directions_map_back_to_the_human_distance(arm: ArmModel) -> None:
    """The human-equivalent wrist of a NAO posture keeps its arm directions."""
    q = rest(arm.side)
    points = arm.fk(q)
    wrist = human_wrist(points)
    upper = points.elbow - points.shoulder
    expected_elbow = paper_grid.UPPER_ARM * upper / np.linalg.norm(upper)
    fore = wrist - expected_elbow
    assert np.linalg.norm(fore) == pytest.approx(paper_grid.FOREARM)
    assert np.allclose(
        fore / np.linalg.norm(fore),
        (points.wrist - points.elbow) / np.linalg.norm(points.wrist - points.elbow),
    )
    assert human_distance_ratio(arm, q, q) == 0.0


def test_default_reach_durations_are_human_and_time_the_reach() -> None:
    """Reaches from rest to postures across the joint ranges get 0.3-2 s."""
    arm = load_arm("right")
    limits = motion_limits(arm.limits)
    rng = np.random.default_rng(4)
    start = rest(arm.side)
    for goal in rng.uniform(arm.limits.lower, arm.limits.upper, (20, 5)):
        duration = reach_duration(arm, start, goal)
        assert MIN_DURATION <= duration < 2.0
    gentle = start + np.array([-0.3, 0.0, 0.0, 0.2, 0.0])
    wanted = reach_duration(arm, start, gentle)
    out = time_path(np.linspace(start, gentle, 60), limits, duration=wanted)
    assert out.duration == pytest.approx(wanted, abs=0.011)
