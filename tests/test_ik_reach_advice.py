"""A target out of reach names the plain mistake behind it: units or arm."""

from __future__ import annotations

import numpy as np
import pytest

from armplan.cli.main import main
from services.ik import check_reachable
from services.ik.reach_advice import reach_advice, within_reach
from services.planner.path_reach import check_path_within_reach
from shared.errors import UnreachableTargetError
from shared.messages import WristPath
from shared.robot import load_arm

#: The docs' reach target for the right arm [m].
GOAL = (0.12, -0.13, 0.05)


def refusal(arm: str, target: tuple[float, float, float]) -> UnreachableTargetError:
    with pytest.raises(UnreachableTargetError) as refused:
        check_reachable(load_arm(arm), np.array(target))
    return refused.value


@pytest.mark.parametrize(
    "target,unit,size",
    [
        ((120.0, -130.0, 50.0), "millimetres", 1000),
        ((12.0, -13.0, 5.0), "centimetres", 100),
    ],
)
def test_a_target_in_other_units_says_which_and_the_metres(
    target: tuple[float, float, float], unit: str, size: int
) -> None:
    """(120, -130, 50) was "183.7513 m from the right shoulder" and no more."""
    error = refusal("right", target)
    advice = (
        f"positions are in metres; it looks like {unit}: (0.12, -0.13, 0.05) m "
        f"is within reach (divide by {size})"
    )
    assert error.message.endswith(f"from it: {advice}")
    assert error.evidence["advice"] == advice
    assert within_reach(load_arm("right"), [v / size for v in target])


def test_a_target_of_the_other_arm_names_it_and_the_mirror_image() -> None:
    """The right arm's target asked for the left arm (or given in a frame
    with y mirrored): "0.2625 m from the left shoulder" and no more."""
    error = refusal("left", GOAL)
    assert error.evidence["advice"] == (
        "it is within the right arm's reach (torso frame: y points to NAO's "
        "left); ask for the right arm, or for the left arm at its mirror image "
        "(0.12, 0.13, 0.05) m"
    )
    check_reachable(load_arm("left"), np.array([0.12, 0.13, 0.05]))  # no raise


@pytest.mark.parametrize(
    "target",
    [(0.5, -0.12, 0.05), (1.2, -1.3, 0.5), (1e308, 0.0, 0.0), (120.0, 130.0, 50.0)],
    ids=["metres-too-far", "near-the-chest-in-mm-or-cm", "huge", "mm-other-arm"],
)
def test_no_advice_where_no_plain_mistake_explains_it(
    target: tuple[float, float, float],
) -> None:
    """(1.2, -1.3, 0.5) read in cm or mm lies within the shell of reach
    but inside NAO's chest: no one meant that."""
    error = refusal("right", target)
    assert error.evidence["advice"] == ""
    assert error.message.endswith("the wrist reaches 0.1141..0.1617 m from it")
    assert reach_advice(load_arm("right"), target) == ""


def test_a_wrist_path_in_millimetres_says_so_at_its_sample() -> None:
    arm = load_arm("right")
    path = WristPath(
        arm=arm.side,
        times=[0.0, 0.5, 1.0],
        positions=[[120.0, -130.0, 50.0], [110.0, -120.0, 40.0], [100.0, -140.0, 0.0]],
    )
    with pytest.raises(UnreachableTargetError) as refused:
        check_path_within_reach(arm, path)
    assert refused.value.message.startswith("wrist-path sample 0 (t = 0.000 s)")
    assert "it looks like millimetres: (0.12, -0.13, 0.05) m" in refused.value.message


def test_the_command_line_prints_the_advice(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", "--target", "120", "-130", "50"]) == 1
    err = capsys.readouterr().err
    assert "183.7513 m from the right shoulder" in err
    assert "it looks like millimetres: (0.12, -0.13, 0.05) m" in err


def test_no_other_arm_for_a_target_inside_the_chest() -> None:
    """(0, -0.05, 0.05), too near the right shoulder, lies in the left arm's
    shell of reach, but 0.07 m from the torso's centre: it was "ask for the
    left arm, or for the right arm at its mirror image (0, 0.05, 0.05) m"."""
    error = refusal("right", (0.0, -0.05, 0.05))
    assert error.evidence["advice"] == ""


def path_of(arm: str, positions: list[list[float]]) -> WristPath:
    times = [0.5 * k for k in range(len(positions))]
    return WristPath(arm=load_arm(arm).side, times=times, positions=positions)


@pytest.mark.parametrize(
    "arm,positions",
    [
        ("right", [[0.12, -0.13, 0.05], [120.0, -130.0, 50.0], [0.11, -0.12, 0.04]]),
        ("left", [[0.12, 0.1, 0.05], [0.12, -0.13, 0.05]]),
    ],
    ids=["one-sample-mistyped", "crossing-the-midline"],
)
def test_no_advice_for_a_path_that_it_fits_at_one_sample_only(
    arm: str, positions: list[list[float]]
) -> None:
    """A path in metres with one sample typed 120 was "it looks like
    millimetres (divide by 1000)"; one from the left arm's side across the
    midline was "ask for the right arm", whose reach its start is out of."""
    with pytest.raises(UnreachableTargetError) as refused:
        check_path_within_reach(load_arm(arm), path_of(arm, positions))
    assert refused.value.evidence["advice"] == ""


def test_a_path_of_the_other_arm_says_to_negate_every_y() -> None:
    path = path_of("left", [[0.12, -0.13, 0.05], [0.11, -0.12, 0.04]])
    with pytest.raises(UnreachableTargetError) as refused:
        check_path_within_reach(load_arm("left"), path)
    assert refused.value.evidence["advice"] == (
        "it is within the right arm's reach (torso frame: y points to NAO's "
        "left); ask for the right arm, or for the left arm with every y negated"
    )
