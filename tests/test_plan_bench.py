"""The planning benchmark runs and reports positive figures (no timing asserted)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armplan.bench import ikpy_peer, plan_cost, plan_parts
from armplan.cli.main import main
from services.planner.pipeline import plan
from shared.messages import PlanRequest, ReachTarget
from shared.robot import load_arm

#: A short reach near the hanging right arm: 31 path points.
SHORT = PlanRequest(targets=[ReachTarget(position=(0.03, -0.13, -0.05))])
RATIOS = ["toppra_over_plan", "ikpy_over_plan"]
RATIOS += ["toppra_over_timing", "ikpy_over_tracking"]
TIMES = ["plan_mp_ms", "plan_least_norm_ms", "plan_single_ms", "toppra_ms"]
TIMES += ["ikpy_ms", "ik_tracking_per_point_us", "decision_per_point_us"]
TIMES += [f"part_{name}_ms" for name in plan_parts.PARTS]


def test_the_ikpy_chain_is_the_arm_of_the_urdf() -> None:
    """ikpy's chain, read from the project's URDF, puts the wrist where
    armplan's forward kinematics does, at random postures (seeded)."""
    arm = load_arm("right")
    chain = ikpy_peer.wrist_chain(arm)
    rng = np.random.default_rng(11)
    for _ in range(20):
        q = rng.uniform(arm.limits.lower, arm.limits.upper)
        np.testing.assert_allclose(
            ikpy_peer.wrist_of(chain, q), arm.fk(q).wrist, atol=1e-12
        )


def test_figures_of_a_short_reach() -> None:
    """Every figure is there; times and ratios are positive numbers; the
    given reach is the one timed; the progress callback runs once per timed
    call; ikpy solves the path."""
    calls: list[None] = []
    cost = plan_cost.run(2, 1, lambda: calls.append(None), reach=SHORT)
    figures = cost.figures()
    assert len(calls) == plan_cost.steps(2, 1)
    assert cost.points == 31
    # this reach's duration, not the one-second reach's
    assert cost.duration == plan(SHORT).trajectory.duration
    for key in RATIOS + TIMES:
        assert math.isfinite(figures[key]) and figures[key] > 0.0, key
    assert figures["plan_points"] == cost.points == cost.parts.points
    assert figures["ikpy_reached_fraction"] > 0.9
    assert cost.plans.keys() == {"mp", "least-norm", "single"}


def test_bad_counts_are_refused(capsys: pytest.CaptureFixture[str]) -> None:
    """--repeats 0 or --ikpy-passes 0: exit 1, the option named."""
    assert main(["bench", "--repeats", "0"]) == 1
    assert "--repeats must be at least 1" in capsys.readouterr().err
    assert main(["bench", "--ikpy-passes", "0"]) == 1
    assert "--ikpy-passes must be at least 1" in capsys.readouterr().err
