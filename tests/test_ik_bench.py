"""The IK benchmark times ours and both peers on the same targets (no timing)."""

from __future__ import annotations

import math

import pytest

from armplan.bench import ik_cost


def test_ours_and_both_peers_solve_the_same_targets() -> None:
    """Each of ours, SLSQP, the eq. 14 step and ikpy is timed once per target;
    the progress callback runs once per timed call; ratios are the quotients
    of the times they compare."""
    calls: list[None] = []
    cost = ik_cost.run(3, seed=5, after=lambda: calls.append(None))
    assert len(calls) == ik_cost.steps(3) == 12
    for timing in (cost.ours, cost.peer, cost.step, cost.ikpy):
        assert len(timing.samples) == 3 and timing.mean > 0.0
    f = cost.figures()
    assert f["targets"] == 3.0
    assert f["speedup_vs_slsqp"] == pytest.approx(
        f["slsqp_per_target_ms"] / f["ik_per_target_ms"]
    )
    assert f["speedup_vs_ikpy"] == pytest.approx(
        f["ikpy_per_target_ms"] / f["ik_per_target_ms"]
    )
    assert f["ik_reached_fraction"] == 1.0  # the targets are FK of postures
    assert 0.0 <= f["ikpy_ik_reached_fraction"] <= 1.0
    gap = "tpe_gap_on_common_targets_j"  # NaN if SLSQP reached none of them
    assert all(math.isfinite(v) for k, v in f.items() if k != gap)
