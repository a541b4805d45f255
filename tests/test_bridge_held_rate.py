"""Frames refused only as NAOqi holds them (32 bits) are offered a lower rate."""

from __future__ import annotations

import json
import pathlib
from functools import partial

import numpy as np
import pytest
from test_bridge_float32 import late_move

from armplan.cli.main import main
from armplan.demo.task import load_task
from bridge import FrameLimits, checked_frames
from bridge.held_rate import HELD_RATES, held_advice
from bridge.minimum_jerk import minimum_jerk_trajectory
from services.planner.pipeline import plan
from shared.errors import TrajectoryRefusedError
from shared.robot.postures import rest

LIMITS = FrameLimits.for_arm("right")


@pytest.mark.parametrize("behavior", [False, True], ids=["python", "behavior"])
def test_a_rate_that_passes_is_offered(behavior: bool) -> None:
    """A late move at 1000 fps breaks RElbowRoll's jerk limit only with its
    times in 32 bits; the refusal said frames further apart suffer less,
    not which rate passes. It names one, and frames at it pass."""
    with pytest.raises(TrajectoryRefusedError) as refused:
        checked_frames(late_move(), 1000.0, LIMITS, behavior=behavior)
    assert refused.value.message.endswith(
        "frames further apart suffer less from it): at 500 fps it would not"
    )
    checked_frames(late_move(), 500.0, LIMITS, behavior=behavior)


def test_the_demo_s_behavior_is_offered_the_rate_its_curve_keeps(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The demo's trajectory as a behavior at 1000 fps: refused in 32 bits.
    Its frames pass at 500 fps, but the curve Choregraphe plays through
    them breaks the hand's jerk limit: the rate offered is the highest
    whose behavior passes every check, as exported (250 fps)."""
    trajectory = plan(load_task().plan_request()).trajectory
    path = tmp_path / "trajectory.json"
    path.write_text(trajectory.to_json())
    out = tmp_path / "b.xar"
    export = ["export", "choregraphe", str(path), "-o", str(out), "--rate"]
    assert main([*export, "1000"]) == 1
    err = capsys.readouterr().err
    assert "as NAOqi holds them; frames further apart suffer less from it)" in err
    assert err.rstrip().endswith(": at 250 fps it would not")
    assert main([*export, "500"]) == 1 and not out.exists()
    assert "on the curve Choregraphe plays" in capsys.readouterr().err
    assert main([*export, "250", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rate"] == 250


def test_no_rate_is_offered_when_none_passes() -> None:
    """Below the lowest rate tried there is none to offer; a move too fast
    for every rate is refused at each tried, and says so."""
    make = partial(checked_frames, late_move(), limits=LIMITS)
    assert held_advice(make, min(HELD_RATES)) == (
        "no frame rate is offered: plan the movement slower (lower "
        "accelerations and jerks)"
    )
    start = rest("right")
    target = start + np.array([0.0, 0.0, 0.0, 0.8, 0.0])
    fast = minimum_jerk_trajectory("right", [start, target], [0.05], 1000.0)
    advice = held_advice(partial(checked_frames, fast, limits=LIMITS), 1000.0)
    assert advice.startswith(
        "no frame rate is offered (500, 250, 200, 125, 100, 50, 40, 25 fps "
        "were refused too)"
    )
