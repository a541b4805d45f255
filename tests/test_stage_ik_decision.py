"""The ik stage tracks a path only with the decision made for that path."""

from __future__ import annotations

import numpy as np
import pytest

from services.planner.stages import decide, default_decider, path_ik
from services.planner.wrist_path import reach_path
from shared.errors import InvalidInputError
from shared.messages import DecideRequest, Decision, PathIKRequest, WristPath, parse
from shared.robot import Side, load_arm
from shared.robot.postures import rest


def _path(side: Side, scale: float = 1.0) -> WristPath:
    """A 1 s reach from rest for ``side`` (times stretched by ``scale``)."""
    arm = load_arm(side)
    goal = np.array((0.12, -0.10 * side.sign, 0.05))
    path = reach_path(arm, rest(side), goal, 1.0)
    return WristPath(
        arm=side,
        times=(scale * path.times).tolist(),
        positions=[tuple(p) for p in path.positions.tolist()],
    )


@pytest.fixture(scope="module")
def right_decision() -> Decision:
    decision, _ = decide(default_decider(), DecideRequest(path=_path(Side.RIGHT)))
    return decision


def _ik_json(path: WristPath, decision: Decision) -> str:
    """A PathIKRequest as the ik service reads it off the bus."""
    return (
        f'{{"path": {path.model_dump_json()}, '
        f'"decision": {decision.model_dump_json()}}}'
    )


def test_the_decision_made_for_the_path_is_tracked(right_decision: Decision) -> None:
    """The matching decision passes and drives the tracking."""
    request = parse(PathIKRequest, _ik_json(_path(Side.RIGHT), right_decision))
    joint_path = path_ik(request)
    assert joint_path.arm is Side.RIGHT
    assert joint_path.primitives == right_decision.primitives


def test_a_decision_for_the_other_arm_is_refused_naming_both(
    right_decision: Decision,
) -> None:
    """A left path with the right arm's decision (same count, same times)."""
    left = _path(Side.LEFT)
    assert left.times == right_decision.times
    with pytest.raises(InvalidInputError, match=r"decision.*right arm.*path.*left"):
        parse(PathIKRequest, _ik_json(left, right_decision))


def test_a_decision_for_other_times_is_refused_naming_both(
    right_decision: Decision,
) -> None:
    """A decision of a 1 s path for the same path stretched to 2 s."""
    slow = _path(Side.RIGHT, scale=2.0)
    assert len(slow.times) == len(right_decision.times)
    with pytest.raises(InvalidInputError) as caught:
        parse(PathIKRequest, _ik_json(slow, right_decision))
    assert caught.value.field == "decision"
    k = next(
        i
        for i, (a, b) in enumerate(zip(right_decision.times, slow.times, strict=True))
        if a != b
    )
    assert f"point {k} at t = {right_decision.times[k]!r} s in the decision" in str(
        caught.value
    )
    assert f"t = {slow.times[k]!r} s in the path" in str(caught.value)


def test_a_decision_of_another_length_is_refused(right_decision: Decision) -> None:
    """Every other point of the path: the counts are named."""
    path = _path(Side.RIGHT)
    half = path.model_copy(
        update={"times": path.times[::2], "positions": path.positions[::2]}
    )
    with pytest.raises(InvalidInputError, match=r"decision has \d+ points, the wrist"):
        parse(PathIKRequest, _ik_json(half, right_decision))
