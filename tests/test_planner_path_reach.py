"""Every sample of a wrist path within the arm's reach, checked in one place."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from services.ik import check_reachable
from services.planner.path_reach import STAGE_SLACK, check_path_within_reach
from services.planner.stages import LocalStages, decide, path_ik
from shared.errors import UnreachableTargetError
from shared.messages import DecideRequest, Method, PathIKRequest, WristPath
from shared.robot import ArmModel, load_arm
from shared.robot.postures import rest


def beyond(arm: ArmModel, out: float) -> tuple[float, float, float]:
    """A point ``out`` beyond the arm's farthest reach [m], in front."""
    way = np.array([1.0, -0.3, 0.3]) / np.linalg.norm([1.0, -0.3, 0.3])
    point = arm.fk(rest(arm.side)).shoulder + way * (arm.reach[1] + out)
    return (float(point[0]), float(point[1]), float(point[2]))


def hanging_path(arm: ArmModel, sample: tuple[float, float, float]) -> WristPath:
    """Eleven samples 10 ms apart at the hanging wrist, the eighth ``sample``."""
    wrist = tuple(float(v) for v in arm.fk(rest(arm.side)).wrist)
    positions = [wrist] * 11
    positions[7] = sample
    times = [0.01 * k for k in range(11)]
    return WristPath(arm=arm.side, times=times, positions=positions)


def test_a_sample_is_judged_as_one_target_is(arm: ArmModel) -> None:
    """0.2 mm beyond the reach: refused as a target and as sample 7, with
    the same words after where it came from."""
    point = beyond(arm, 2e-4)
    with pytest.raises(UnreachableTargetError) as target:
        check_reachable(arm, np.array(point))
    with pytest.raises(UnreachableTargetError) as sample:
        check_path_within_reach(arm, hanging_path(arm, point))
    assert sample.value.message == f"wrist-path sample 7 (t = 0.070 s): {target.value}"


@pytest.mark.parametrize("out", [5e-4, 2e-3])
def test_the_stages_allow_a_hair_out_of_the_reach(arm: ArmModel, out: float) -> None:
    """With ``STAGE_SLACK`` (1 mm): 0.5 mm out passes, 2 mm out is refused."""
    path = hanging_path(arm, beyond(arm, out))
    if out < STAGE_SLACK:
        check_path_within_reach(arm, path, STAGE_SLACK)
        return
    with pytest.raises(UnreachableTargetError, match=r"^wrist-path sample 7 "):
        check_path_within_reach(arm, path, STAGE_SLACK)


def test_a_huge_sample_is_named_without_an_overflow_warning() -> None:
    """1e308 m away: refused, its distance printed, no numpy warning."""
    arm = load_arm("right")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UnreachableTargetError, match="is 1e\\+308 m from"):
            check_path_within_reach(arm, hanging_path(arm, (1e308, 0.0, 0.0)))


@pytest.mark.parametrize("stage", ["decide", "ik", "local"])
def test_the_stages_refuse_a_sample_out_of_reach(stage: str) -> None:
    """The decide and ik stages (what the services run) refuse a path with a
    sample 2 mm out, naming it, before any tracking."""
    arm = load_arm("right")
    path = hanging_path(arm, beyond(arm, 2e-3))
    with pytest.raises(UnreachableTargetError, match=r"^wrist-path sample 7 "):
        if stage == "decide":
            decide(LocalStages().decider, DecideRequest(path=path))
        elif stage == "ik":
            path_ik(PathIKRequest(path=path, method=Method.LEAST_NORM))
        else:
            LocalStages().decide(DecideRequest(path=path))
