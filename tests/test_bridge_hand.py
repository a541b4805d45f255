"""The hand as one more actuator of the bridge: checks, the simulated NAO, exports.

A trajectory with a hand channel (``Trajectory.hand``) is checked, sent and
exported with ``RHand`` beside the arm's joints: its range (open fraction
0..1) and its speed, acceleration and jerk limits are held as a joint's;
the bridge process plays it on the simulated NAO process through real
libqi, and the Choregraphe behavior and the Python export carry it.
"""

from __future__ import annotations

import ast
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import qi
from test_bridge import BridgeProcess, commands_logged

from armplan.cli.main import main
from bridge import (
    FrameLimits,
    behavior_xml,
    checked_frames,
    frame_velocities,
    python_script,
)
from bridge.choregraphe import timeline_from_xml
from bridge.hand import with_hand_joint
from bridge.interpolation import positions_at
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from services.planner.pipeline import plan
from shared.errors import TrajectoryRefusedError
from shared.messages import ExecuteReply, ExecuteRequest, PlanRequest, Trajectory, parse

GRASP = (0.12, -0.10, 0.05)
PLACE = (0.10, -0.14, 0.0)


@pytest.fixture(scope="module")
def grasp() -> Trajectory:
    """Reach, close the hand (0.3 s dwell, lengthened to 0.45 s), carry, place."""
    request = parse(
        PlanRequest,
        {
            "targets": [
                {"position": GRASP, "dwell": 0.3, "hand": "close"},
                {"position": PLACE, "dwell": 0.2},
            ]
        },
    )
    return plan(request).trajectory


def _with_hand(trajectory: Trajectory, hand: np.ndarray) -> Trajectory:
    """``trajectory`` with another hand channel, whose speeds are not known."""
    return trajectory.model_copy(
        update={
            "hand": hand.tolist(),
            "hand_velocities": None,
            "hand_accelerations": None,
        }
    )


@pytest.mark.parametrize("rate", [200.0, 500.0, 1000.0])
def test_a_planned_hand_passes_wherever_the_arm_does(rate: float) -> None:
    """Close at one target, open at the next (100 Hz plan, the hand within
    its 33 /s^2 and 666 /s^3): the frames pass every check at 200, 500 and
    1000 fps, as the arm's alone do. The hand's curve between samples went
    through central differences, kinked at each move's ends, and was refused
    at 500 fps (RHand jerk 1825 /s^3 > 1666) and at 1000 fps; the frames held
    inside 0..1 by clipping kinked where the hand left a rest at 1."""
    targets = [
        {"position": GRASP, "hand": "close"},
        {"position": PLACE, "hand": "open"},
    ]
    trajectory = plan(parse(PlanRequest, {"targets": targets})).trajectory
    arm = trajectory.model_copy(
        update={"hand": None, "hand_velocities": None, "hand_accelerations": None}
    )
    limits = FrameLimits.for_arm("right")
    checked_frames(arm, rate, limits)
    frames = checked_frames(trajectory, rate, limits)
    hand = np.array([row[-1] for row in frames.positions])
    assert hand.min() > 0.0 and hand.max() < 1.0


def test_the_hands_curve_keeps_its_rests_and_its_range(grasp: Trajectory) -> None:
    """Between samples, the hand's curve rests where the hand rests (exactly
    its value) and stays within 0..1 unclipped: it goes through the planned
    speeds, 0 at a rest."""
    joint = with_hand_joint(grasp)
    t = np.asarray(grasp.times)
    fine = np.linspace(0.0, t[-1] - t[0], 20 * len(t))
    curve = positions_at(joint, fine)[:, -1]
    hand = np.asarray(grasp.hand)
    assert curve.min() >= 0.0 and curve.max() <= 1.0
    still = np.flatnonzero(np.diff(hand) == 0.0)  # sample k to k + 1 at rest
    for k in still:
        inside = (fine >= t[k] - t[0]) & (fine <= t[k + 1] - t[0])
        assert np.all(curve[inside] == hand[k])


def test_the_hand_is_one_more_joint_of_the_frames(grasp: Trajectory) -> None:
    """The frames move RShoulderPitch..RWristYaw and then RHand, whose frames
    follow the hand channel (open at the start, shut at the end)."""
    frames = checked_frames(grasp, 25.0, FrameLimits.for_arm("right"))
    assert frames.joint_names == [*grasp.joint_names, "RHand"]
    hand = np.array([row[-1] for row in frames.positions])
    assert frames.start[-1] == pytest.approx(1.0, abs=1e-6)
    assert hand[-1] == pytest.approx(0.0, abs=1e-6)
    assert np.all(np.diff(hand) <= 1e-12)  # it only closes


def test_a_hand_out_of_range_or_too_fast_is_refused(grasp: Trajectory) -> None:
    """An open fraction of 1.2, a jump from open to shut in one sample, a
    sudden start at 5 /s: refused naming RHand, the quantity, the frame and
    the limit in the hand's units (no radians)."""
    limits = FrameLimits.for_arm("right")
    hand = np.asarray(grasp.hand)
    over = hand.copy()
    over[:5] = 1.2
    with pytest.raises(TrajectoryRefusedError) as refused:
        checked_frames(_with_hand(grasp, over), 25.0, limits)
    assert refused.value.joint == "RHand" and refused.value.quantity == "position"
    assert "open fraction 1.2000 at sample 0 (t = 0.000 s) is outside its range " in (
        refused.value.message
    )
    assert "[0.0000, 1.0000]" in refused.value.message
    assert "rad" not in refused.value.message
    jump = np.where(np.arange(len(hand)) < len(hand) // 2, 1.0, 0.0)
    with pytest.raises(TrajectoryRefusedError) as refused:
        checked_frames(_with_hand(grasp, jump), 25.0, limits)
    assert refused.value.joint == "RHand" and refused.value.quantity == "velocity"
    assert "exceeds its limit 8.330 /s" in refused.value.message
    t = np.asarray(grasp.times)
    ramp = np.clip(1.0 - 5.0 * (t - 0.48), 0.0, 1.0)  # 5 /s from rest at once
    with pytest.raises(TrajectoryRefusedError) as refused:
        checked_frames(_with_hand(grasp, ramp), 25.0, limits)
    assert refused.value.joint == "RHand"
    assert refused.value.quantity == "acceleration"
    assert "exceeds its limit 83.30 /s^2" in refused.value.message


def test_a_trajectory_naming_a_hand_twice_is_refused(grasp: Trajectory) -> None:
    """The hand as a channel and as a joint column at once: a typed error."""
    twice = with_hand_joint(grasp).model_copy(update={"hand": grasp.hand})
    with pytest.raises(Exception, match="give the hand once"):
        checked_frames(twice, 25.0, FrameLimits.for_arm("right"))


def test_the_behavior_and_the_python_export_carry_the_hand(grasp: Trajectory) -> None:
    """behavior.xar has an RHand curve in open fraction (unit="1", values
    0..1 as written, as libqicore-compat's timeline sends unit 1 unscaled),
    keyed like the joints, its tangents' slopes the hand's speed in open
    fraction per second where it moves inside its range; its script box
    brings RHand to its start; the Python export appends RHand's keys (the
    open fraction) to its lists."""
    frames = checked_frames(grasp, 25.0, FrameLimits.for_arm("right"), behavior=True)
    velocities = frame_velocities(grasp, frames)
    text = behavior_xml(frames, velocities=velocities)
    assert 'actuator="RHand" recordable="1" mute="0" unit="1"' in text
    assert 'actuator="RShoulderPitch" recordable="1" mute="0" unit="0"' in text
    keys = timeline_from_xml(text)
    assert keys.names[-1] == "RHand"
    np.testing.assert_array_equal(keys.frames[-1], keys.frames[0])
    hand = keys.angles("RHand")
    assert hand.min() >= 0.0 and hand.max() <= 1.0
    assert hand[0] == pytest.approx(1.0, abs=2e-6)  # held inside the range
    assert hand[-1] == pytest.approx(0.0, abs=2e-6)
    speed = velocities[:, -1]
    inside = (hand[: len(speed)] > 0.01) & (hand[: len(speed)] < 0.99)
    assert np.abs(speed[inside]).max() > 0.5  # the hand moves, in fraction/s
    slopes = keys.slopes("RHand")[: len(speed)]
    np.testing.assert_allclose(slopes[inside, 0], speed[inside], atol=1e-6)
    np.testing.assert_allclose(slopes[inside, 1], speed[inside], atol=1e-6)
    assert '"RHand"]' in text and "self.joint_names, now, self.first_key" in text
    script = python_script(frames)
    module = ast.parse(script)
    assert 'names.append("RHand")' in script
    namespace: dict[str, Any] = {}
    code = compile(module, "play.py", "exec")
    exec(code, namespace)  # the lists only; main() is not run
    assert namespace["names"][-1] == "RHand"
    np.testing.assert_allclose(
        namespace["keys"][-1], [row[-1] for row in frames.positions]
    )
    assert namespace["start"][-1] == frames.start[-1]


@pytest.fixture
def bridge(sim: SimProcess) -> Iterator[BridgeProcess]:
    process = BridgeProcess(sim.url)
    try:
        yield process
    finally:
        process.close()


def _hand_of(sim: SimProcess) -> float:
    session = qi.Session()
    session.connect(sim.url)
    try:
        return float(session.service("ALMotion").getAngles("RHand", True)[0])
    finally:
        session.close()


def test_the_simulated_nao_closes_its_hand(
    sim: SimProcess, bridge: BridgeProcess, grasp: Trajectory
) -> None:
    """Through the bridge process and real libqi: the sim's hand starts shut
    (0), the approach opens it to the trajectory's start, the dwell closes it;
    getAngles gives RHand 0 at the end; the hand is in the call, the measured
    states and the report (within 0.02 of its command), the arm's joints
    within a degree."""
    assert _hand_of(sim) == 0.0
    reply = ExecuteReply.model_validate(
        bridge.execute(ExecuteRequest(trajectory=grasp))
    )
    assert reply.approach_duration >= 0.5  # the hand opened first
    assert reply.states.joint_names[-1] == "RHand"
    measured = np.array(reply.states.measured)[:, -1]
    assert measured.max() == pytest.approx(1.0, abs=0.02)
    assert _hand_of(sim) == pytest.approx(0.0, abs=1e-6)
    report = reply.report
    assert "RHand" not in report.tracking_rms_deg
    assert report.hand_tracking_rms is not None and report.hand_tracking_rms < 0.02
    assert max(report.tracking_rms_deg.values()) < 1.0
    assert sim.log_path is not None
    log = read_log(sim.log_path)
    assert not [e for e in log if e["event"] == "refused"]
    calls = [e for e in log if e.get("method") == "angleInterpolation"]
    assert calls and all("RHand" in e["names"] for e in calls if "names" in e)


def test_a_hand_too_fast_never_reaches_the_robot(
    sim: SimProcess, bridge: BridgeProcess, grasp: Trajectory
) -> None:
    """A hand that snaps shut in one sample: refused by the bridge process
    naming RHand; the simulated NAO's log shows no command."""
    hand = np.where(np.arange(len(grasp.times)) < 100, 1.0, 0.0)
    error = bridge.execute(ExecuteRequest(trajectory=_with_hand(grasp, hand)))["error"]
    assert error["kind"] == "trajectory_refused"
    assert error["evidence"]["joint"] == "RHand"
    assert "RHand speed" in error["message"]
    time.sleep(0.1)
    assert commands_logged(sim) == []


def test_armplan_export_writes_the_hand(
    grasp: Trajectory, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``armplan export`` of a trajectory file with a hand channel: the
    behavior has the RHand curve, the script RHand's keys; a hand out of
    range is refused with nothing written."""
    path = tmp_path / "trajectory.json"
    path.write_text(grasp.to_json())
    behavior, script = tmp_path / "behavior.xar", tmp_path / "play.py"
    assert main(["export", "choregraphe", str(path), "-o", str(behavior)]) == 0
    assert 'actuator="RHand"' in behavior.read_text()
    assert main(["export", "python", str(path), "-o", str(script)]) == 0
    assert 'names.append("RHand")' in script.read_text()
    bad = _with_hand(grasp, np.full(len(grasp.times), -0.5))
    path.write_text(bad.to_json())
    capsys.readouterr()
    assert main(["export", "python", str(path), "-o", str(tmp_path / "x.py")]) == 1
    err = capsys.readouterr().err
    assert "RHand open fraction -0.5000" in err and "nothing was written" in err
    assert not (tmp_path / "x.py").exists()
