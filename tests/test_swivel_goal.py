"""An elbow swivel goal in degrees is refused, saying its radians."""

from __future__ import annotations

import math

import pytest
from armplan_cli import armplan

from shared.errors import InvalidInputError
from shared.messages import IKRequest, parse

#: The README's swivel example: a bent arm whose wrist S_R E_P W_R holds.
HELD_WRIST = (
    *("--target", "0.14092095", "-0.13101531", "0.09501147"),
    *("--start", "0.3", "-0.3", "1.0", "0.9", "0.0"),
    *("--primitive", "S_R E_P W_R"),
)


@pytest.mark.parametrize(
    "goal", [0.0, math.pi, 2 * math.pi, 6.28318531, -1.0, -2 * math.pi, 4 * math.pi]
)
def test_a_goal_within_two_turns_is_taken_as_given(goal: float) -> None:
    """0, pi, 2 pi (as typed, a little over), negative, and a mirror 2 pi - phi."""
    request = parse(IKRequest, {"target": (0.12, -0.13, 0.05), "swivel": goal})
    assert request.swivel == goal


@pytest.mark.parametrize(
    ("goal", "said"),
    [
        (90.0, "looks like degrees: angles are in radians, and 90 deg is 1.5708 rad"),
        (-180.0, "and -180 deg is -3.1416 rad"),
        (4 * math.pi + 0.01, "deg is 0.2195 rad"),
        (400.0, "give it within -4 pi..4 pi rad"),
        (1e300, "give it within -4 pi..4 pi rad"),
    ],
)
def test_a_goal_beyond_two_turns_is_refused(goal: float, said: str) -> None:
    """A goal over 4 pi from 0 reads as degrees (it was wrapped to a turn)."""
    with pytest.raises(InvalidInputError) as caught:
        parse(IKRequest, {"target": (0.12, -0.13, 0.05), "swivel": goal})
    assert caught.value.field == "swivel"
    assert "more than two turns" in str(caught.value)
    assert said in str(caught.value)


def test_swivel_in_degrees_on_the_command_line_is_refused() -> None:
    """``--swivel 90`` moved the elbow to 2.0354 rad (90 rad less 14 turns), exit 0."""
    out = armplan("ik", *HELD_WRIST, "--swivel", "90")
    assert out.returncode == 1, out.stdout
    assert out.stdout == ""
    assert "error: invalid IKRequest: swivel: an elbow swivel of 90 rad" in out.stderr
    assert "90 deg is 1.5708 rad" in out.stderr
    assert "Traceback" not in out.stderr


def test_swivel_in_radians_on_the_command_line_is_solved() -> None:
    """The same request in radians is solved, the swivel reached as asked."""
    out = armplan("ik", *HELD_WRIST, "--swivel", "1.5708")
    assert out.returncode == 0, out.stderr
    assert "elbow swivel 1.5708 rad reached (asked 1.5708 rad)" in out.stdout


def test_the_left_arms_swivel_0_reads_as_reached_not_a_turn_off() -> None:
    """Asked 0, the left arm's swivel came back as 2 pi - 4e-9 (in [0, 2 pi))
    and the text said "6.2832 rad reached (asked 0.0000 rad)"."""
    out = armplan(
        "ik",
        "--arm",
        "left",
        *("--target", "0.14092095", "0.13101531", "0.09501147"),
        *("--start", "0.3", "0.3", "-1.0", "-0.9", "0.0"),
        *("--primitive", "S_R E_P W_R", "--swivel", "0"),
    )
    assert out.returncode == 0, out.stderr
    assert "elbow swivel 0.0000 rad reached (asked 0.0000 rad)" in out.stdout


@pytest.mark.parametrize(
    ("angle", "near", "shown"),
    [
        (2 * math.pi - 4e-9, 0.0, 0.0),
        (4e-9, 2 * math.pi, 6.2832),
        (1.5708, 1.5708 + 2 * math.pi, 7.854),
        (3.0, -3.0, 3.0 - 2 * math.pi),
    ],
)
def test_a_swivel_is_shown_in_the_turn_of_its_goal(
    angle: float, near: float, shown: float
) -> None:
    from armplan.cli.commands.ik import nearest_turn

    value = nearest_turn(angle, near)
    assert value == pytest.approx(shown, abs=1e-4)
    assert abs(value - near) <= math.pi + 1e-9
    assert math.isclose(math.cos(value), math.cos(angle), abs_tol=1e-4)
