"""The timing benchmark runs and returns positive figures (no timing asserted)."""

from __future__ import annotations

import numpy as np

from armplan.bench import timing_cost
from shared.robot import load_arm
from shared.robot.postures import rest


def test_benchmark_returns_positive_figures_on_a_tiny_path() -> None:
    """Costs and durations of ours and toppra's are positive numbers."""
    start = rest("right")
    path = np.linspace(start, start + np.array([-0.4, 0.1, 0.2, 0.3, 0.0]), 12)
    cost = timing_cost.run(path, repeats=2)
    assert cost.points == 12
    for timing in (cost.fastest, cost.human, cost.peer):
        assert timing.mean > 0.0
    assert cost.fastest_duration > 0.0 and cost.peer_duration > 0.0
    assert cost.human_duration >= cost.fastest_duration
    assert cost.speedup > 0.0 and cost.peer_max_jerk_ratio >= 0.0


def test_the_default_path_is_a_one_second_reach_at_100_hz() -> None:
    """101 postures of the right arm, from rest to the target."""
    q = timing_cost.reach_joint_path()
    arm = load_arm("right")
    assert q.shape == (101, 5)
    assert np.allclose(q[0], rest("right"), atol=0.05)  # first IK step from rest
    assert np.linalg.norm(arm.fk(q[-1]).wrist - timing_cost.TARGET) < 1e-4
