"""The exported scripts' own body check (``bridge.script_body``).

``play.py`` and the behavior's start box move the arm to the start from
wherever it is when they run, without armplan. Their copy of the body
model, in plain Python, agrees with ``shared.robot.body`` (two methods),
runs on a NAO's Python 2.7, and stops ``play.py`` before it sends a move
through NAO's torso, or a trajectory into the other arm where the robot
holds it, against the simulated NAO over libqi.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_bridge_body import ACROSS, AWAY, least_clearance
from test_planner_other_arm import LEFT_ACROSS, START, TARGET
from test_play_runner import python2

from bridge.frames import frames_from_trajectory
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.python_export import write_python
from bridge.script_body import body_source
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from services.planner.pipeline import plan
from shared.libqi import qi
from shared.messages import PlanRequest
from shared.robot import Side, load_arm
from shared.robot.body import BODY, MARGIN, arm_points, closest, other_arm
from shared.robot.postures import rest

NAMES = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
LEFT_NAMES = ["L" + name[1:] for name in NAMES]


def script_namespace(side: str) -> dict[str, Any]:
    namespace: dict[str, Any] = {}
    exec(body_source(side), namespace)
    return namespace


@pytest.mark.parametrize("side", ["right", "left"])
def test_the_scripts_check_agrees_with_the_body_model(side: str) -> None:
    """300 random postures: the same key points as the arm model, and
    refused exactly when ``closest`` is under the margin."""
    arm = load_arm(side)
    namespace = script_namespace(side)
    rng = np.random.default_rng(17)
    q = rng.uniform(arm.limits.lower, arm.limits.upper, size=(300, 5))
    points = arm_points(arm, q)
    refused = 0
    for k, posture in enumerate(q):
        mine = namespace["_arm_points"](list(posture))
        for name, point in mine.items():
            np.testing.assert_allclose(point, points[name][k], rtol=0, atol=1e-12)
        keys = [[float(v)] for v in posture]
        near = closest(arm, [posture]).clearance < MARGIN
        try:
            namespace["check_clear"](list(arm.side.joint_names), keys, [[0.5]] * 5)
        except RuntimeError as error:
            refused += 1
            assert near, error
            assert "at key 1 (t = 0.500 s)" in str(error)
        else:
            assert not near
    assert 5 <= refused <= 60  # about 6 % of uniform postures


def test_the_check_runs_on_python_2() -> None:
    """A NAO's Python 2.7 computes the same clearances' verdicts."""
    exe = python2()
    if exe is None:
        pytest.skip("no Python 2.7 here")
    arm = load_arm("right")
    rng = np.random.default_rng(18)
    postures = rng.uniform(arm.limits.lower, arm.limits.upper, size=(60, 5)).tolist()
    program = body_source("right") + (
        "\nimport json, sys\n"
        "out = []\n"
        "for q in json.loads(sys.stdin.read()):\n"
        "    try:\n"
        "        check_clear(ARM_JOINTS, [[v] for v in q], [[1.0]] * 5)\n"
        "        out.append(True)\n"
        "    except RuntimeError:\n"
        "        out.append(False)\n"
        "print(json.dumps(out))\n"
    )
    done = subprocess.run(
        [exe, "-c", program],
        input=json.dumps(postures),
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    verdicts = json.loads(done.stdout)
    expected = [closest(arm, [q]).clearance >= MARGIN for q in postures]
    assert verdicts == expected
    assert not all(verdicts)


def test_play_py_refuses_a_move_to_the_start_through_the_torso(tmp_path: Path) -> None:
    """The arm held at AWAY; the script of a hold at ACROSS, whose straight
    way from AWAY passes the head and crosses the torso: it exits 1 naming
    the part, and sends no move; from rest, whose way is clear, it plays."""
    assert least_clearance(AWAY, ACROSS).min() < 0
    hold = minimum_jerk_trajectory("right", [ACROSS, ACROSS], [0.6])
    path = write_python(frames_from_trajectory(hold), tmp_path / "play.py")
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        motion.angleInterpolationWithSpeed(NAMES, AWAY.tolist(), 0.5)
        before = moves(log)
        refused = play(path, sim.url)
        after_refusal = moves(log)
        motion.angleInterpolationWithSpeed(NAMES, rest("right").tolist(), 0.5)
        played = play(path, sim.url)
        session.close()
    assert refused.returncode == 1, refused.stderr
    assert refused.stderr.startswith(
        "play.py: error: the move to the start would bring the right "
    )
    assert "NAO's" in refused.stderr
    assert "nothing of it was sent" in refused.stderr
    assert after_refusal == before
    assert played.returncode == 0, played.stderr
    assert moves(log) > after_refusal


def moves(log: Path) -> int:
    """angleInterpolation calls in the sim's log."""
    return sum(
        1
        for e in read_log(log)
        if e["event"] == "call" and e["method"] == "angleInterpolation"
    )


def play(path: Path, url: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(path), url],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def test_a_key_that_is_no_number_is_refused() -> None:
    """NaN compares false with everything: taken as clear, it would pass."""
    namespace = script_namespace("right")
    keys = [[float("nan")], [0.0], [0.0], [0.5], [0.0]]
    with pytest.raises(RuntimeError, match="at key 1"):
        namespace["check_clear"](NAMES, keys, [[0.5]] * 5)


@pytest.mark.parametrize("side", ["right", "left"])
def test_the_scripts_other_arm_agrees_with_the_body_model(side: str) -> None:
    """The other arm's capsules from its angles: the same as ``other_arm``;
    and the check with them refuses exactly when ``closest`` with them is
    under the margin."""
    arm = load_arm(side)
    other = load_arm(Side.LEFT if arm.side is Side.RIGHT else Side.RIGHT)
    namespace = script_namespace(side)
    assert namespace["OTHER_JOINTS"] == list(other.side.joint_names)
    rng = np.random.default_rng(19)
    held = rng.uniform(other.limits.lower, other.limits.upper, size=(40, 5))
    moving = rng.uniform(arm.limits.lower, arm.limits.upper, size=(40, 5))
    refused = 0
    for there, posture in zip(held, moving, strict=True):
        parts = other_arm(other, there)
        mine = namespace["other_arm_parts"](list(there))
        assert [p[0] for p in mine] == [p.name for p in parts]
        for (_, bottom, top, radius), part in zip(mine, parts, strict=True):
            np.testing.assert_allclose(bottom, part.bottom, rtol=0, atol=1e-12)
            np.testing.assert_allclose(top, part.top, rtol=0, atol=1e-12)
            assert radius == part.radius
        near = closest(arm, [posture], BODY + parts).clearance < MARGIN
        keys = [[float(v)] for v in posture]
        try:
            namespace["check_clear"](
                list(arm.side.joint_names), keys, [[0.5]] * 5, others=mine
            )
        except RuntimeError:
            refused += 1
            assert near
        else:
            assert not near
    assert refused >= 1


def test_play_py_refuses_a_trajectory_into_the_other_arm(tmp_path: Path) -> None:
    """The simulated NAO holds its left arm across; the right arm's plan made
    without knowing it runs into it: play.py exits 1 naming the left arm
    and sends nothing; the plan made with ``other_arm`` plays."""

    def exported(other_arm: list[float] | None, name: str) -> Path:
        request = PlanRequest(
            arm="right",
            start=START,
            targets=[{"position": TARGET}],
            other_arm=other_arm,
        )
        trajectory = plan(request).trajectory
        return write_python(frames_from_trajectory(trajectory), tmp_path / name)

    blind, aware = exported(None, "blind.py"), exported(LEFT_ACROSS, "aware.py")
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        motion.angleInterpolationWithSpeed(LEFT_NAMES, LEFT_ACROSS, 0.5)
        motion.angleInterpolationWithSpeed(NAMES, START, 0.5)
        before = moves(log)
        refused = play(blind, sim.url)
        after_refusal = moves(log)
        played = play(aware, sim.url)
        session.close()
    assert refused.returncode == 1, refused.stderr
    assert refused.stderr.startswith(
        "blind.py: error: the trajectory would bring the right "
    )
    assert (
        "NAO's left " in refused.stderr and "nothing of it was sent" in refused.stderr
    )
    assert "armplan plan --other-arm" in refused.stderr
    assert after_refusal == before
    assert played.returncode == 0, played.stderr
    assert moves(log) > after_refusal
