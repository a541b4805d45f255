"""The left arm's IK is the mirror of the right arm's, restarts included."""

from __future__ import annotations

import json

import numpy as np
import pytest

from armplan.cli.main import main
from shared.geometry.swivel import swivel_angle
from shared.messages import IKRequest
from shared.robot import Side, load_arm
from shared.robot.postures import mirror

#: A least-norm solve that fails its first attempt and restarts from seeds
#: (found by a mirror sweep): right start and target [rad, m].
START = (0.3620663529827741, -0.11594668562839616, 1.9032458507880112,
         0.46396890520714473, 0.5418615891533609)  # fmt: skip
TARGET = (-0.007950826449217747, -0.20735782719883689, 0.03713936207049065)
#: NAO's mirror of a right posture onto the left arm: the rolls and yaws flip.
MIRROR = np.array([1.0, -1.0, -1.0, -1.0, -1.0])


def solve(arm: str, start: np.ndarray, target: np.ndarray, capsys) -> np.ndarray:  # type: ignore[no-untyped-def]
    argv = ["ik", "--arm", arm, "--method", "least-norm", "--json"]
    argv += ["--start", *map(repr, map(float, start))]
    argv += ["--target", *map(repr, map(float, target))]
    assert main(argv) == 0
    return np.array(list(json.loads(capsys.readouterr().out)["joints"].values()))


def test_a_restarted_solve_is_mirrored(capsys: pytest.CaptureFixture[str]) -> None:
    """The same seeds for both arms gave the left arm another posture (1.2 rad
    away from the mirror); its seeds are now the mirrors of the right's."""
    start, target = np.array(START), np.array(TARGET)
    right = solve("right", start, target, capsys)
    left = solve("left", MIRROR * start, target * np.array([1.0, -1.0, 1.0]), capsys)
    np.testing.assert_allclose(left, MIRROR * right, atol=1e-9)


@pytest.mark.parametrize("spelling", ["Left", "LEFT", " left "])
def test_the_arm_is_read_in_any_case(
    spelling: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """plan, fk and decide read --arm in any case; ik refused 'Left' ('Input
    should be right or left'). It now solves the left arm."""
    target = TARGET * np.array([1.0, -1.0, 1.0])
    start = MIRROR * np.array(START)
    spelt = solve(spelling, start, target, capsys)
    np.testing.assert_allclose(spelt, solve("left", start, target, capsys))


def test_the_left_arms_swivel_is_the_mirror_2_pi_minus_phi(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """--swivel's help and IKRequest said only "pi: elbow down"; a left-arm
    user could not tell phi is not mirrored for them. Both now say the
    left mirror of phi is 2 pi - phi, which is what the code measures."""
    right, left = load_arm(Side.RIGHT), load_arm(Side.LEFT)
    rng = np.random.default_rng(5)
    span = right.limits.upper - right.limits.lower
    for _ in range(50):
        q = right.limits.lower + rng.random(5) * span
        a, b = right.fk(q), left.fk(mirror(q))
        phi = swivel_angle(a.shoulder, a.elbow, a.wrist)
        mirrored = swivel_angle(b.shoulder, b.elbow, b.wrist)
        gap = (2 * np.pi - phi - mirrored + np.pi) % (2 * np.pi) - np.pi
        assert abs(gap) < 1e-12
    with pytest.raises(SystemExit):
        main(["ik", "--help"])
    shown = " ".join(capsys.readouterr().out.split())
    assert "left arm's mirror of a right-arm phi is 2*pi - phi" in shown
    assert "mirror of a right-arm swivel phi is 2 pi - phi" in " ".join(
        (IKRequest.__doc__ or "").split()
    )
