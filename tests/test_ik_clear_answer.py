"""The ik answer keeps clear of NAO's body (services/ik/solver.py,
``_clear_of_body``; services/ik/elbow_turn.py).

The target check keeps the hand's ball at the wrist clear, but the arm of
the posture found could still come near: 5 of 420 random answers did, one
1.8 mm into the head. Such a posture has its elbow turned about the wrist,
or the answer is refused naming the parts.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from services.ik.solver import solve, solve_request
from shared.errors import ArmplanError, BodyCollisionError
from shared.messages import IKRequest, Method
from shared.robot import load_arm
from shared.robot.body import MARGIN, closest
from tests.armplan_cli import armplan

#: A target whose mp posture puts the hand into the head; turned, clear.
TURNED = (0.0923, -0.0631, 0.1651)
#: A target above the shoulder whose every posture found keeps the upper
#: arm within the margin of the head, turned or not.
REFUSED = (0.054, -0.079, 0.2512)


def _joints(result) -> np.ndarray:
    return np.array(list(result.joints.values()))


def test_a_posture_near_the_body_is_turned_clear_about_its_wrist() -> None:
    """The solver's own posture comes into the head; the answer's keeps the
    margin, with the wrist still on the target and the label of the full
    primitive (every joint moved)."""
    arm = load_arm("right")
    assert closest(arm, [solve(arm, np.array(TURNED)).q]).clearance < 0.0
    result = solve_request(arm, IKRequest(target=TURNED))
    q = _joints(result)
    assert closest(arm, [q]).clearance >= MARGIN
    assert np.linalg.norm(arm.fk(q).wrist - np.array(TURNED)) < 1e-4
    assert result.primitive == "S_R E_PR W_P"


def test_a_named_primitives_posture_is_not_turned_but_refused() -> None:
    with pytest.raises(BodyCollisionError, match="named primitive") as err:
        solve_request(
            load_arm("right"), IKRequest(target=TURNED, primitive="S_R E_PR W_P")
        )
    assert err.value.body_part == "head"


@pytest.mark.parametrize("method", list(Method))
def test_a_posture_no_swivel_takes_clear_is_refused_naming_the_parts(
    method: Method,
) -> None:
    with pytest.raises(BodyCollisionError, match=r"^the posture the IK found") as err:
        solve_request(load_arm("right"), IKRequest(target=REFUSED, method=method))
    assert err.value.arm_part == "upper arm" and err.value.body_part == "head"
    assert "did not take it clear" in str(err.value)


def test_every_answer_keeps_clear_of_the_body() -> None:
    """Targets at the wrist of 150 random postures, each method: every answer
    given keeps the margin (the rest are refused with a typed error), and
    the answers that needed turning were turned."""
    arm = load_arm("right")
    rng = np.random.default_rng(0)
    answered = 0
    for _ in range(150):
        target = tuple(arm.fk(rng.uniform(arm.limits.lower, arm.limits.upper)).wrist)
        for method in Method:
            try:
                result = solve_request(arm, IKRequest(target=target, method=method))
            except ArmplanError:
                continue
            answered += 1
            assert closest(arm, [_joints(result)]).clearance >= MARGIN, target
    assert answered >= 300


def test_the_command_line_says_it_too() -> None:
    done = armplan("ik", "--target", *(str(v) for v in REFUSED), "--json")
    assert done.returncode == 1, done.stderr
    assert json.loads(done.stdout)["error"]["kind"] == "body_collision"
    done = armplan("ik", "--target", *(str(v) for v in TURNED), "--json")
    assert done.returncode == 0, done.stderr
    q = np.array(list(json.loads(done.stdout)["joints"].values()))
    assert closest(load_arm("right"), [q]).clearance >= MARGIN
