"""The simulated NAO, reached only through a real libqi session on 127.0.0.1."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import qi
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.robot import load_arm


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SimProcess]:
    process = SimProcess(log_path=tmp_path_factory.mktemp("sim") / "sim.jsonl")
    process.start()
    try:
        yield process
    finally:
        process.stop()


@pytest.fixture(scope="module")
def motion(sim: SimProcess) -> Iterator[Any]:
    session = qi.Session()
    session.connect(sim.url)
    try:
        yield session.service("ALMotion")
    finally:
        session.close()


def log_of(sim: SimProcess) -> list[dict[str, Any]]:
    assert sim.log_path is not None
    return read_log(Path(sim.log_path))


def received_at(sim: SimProcess, method: str) -> float:
    """When the sim received its last ``method`` call [s, this machine's
    monotonic clock, which the sim's log shares]."""
    calls = [e for e in log_of(sim) if e["event"] == "call" and e["method"] == method]
    return sim_origin(sim) + float(calls[-1]["t"])


def sim_origin(sim: SimProcess) -> float:
    """The monotonic clock at the sim log's ``t = 0`` [s]."""
    return float(next(e["origin"] for e in log_of(sim) if e["event"] == "start"))


def test_it_starts_awake_and_rest_leaves_it_not_awake(
    sim: SimProcess, motion: Any
) -> None:
    """It starts as a NAO standing after wakeUp: awake, every joint stiff.
    robotIsWakeUp is the robot's state, as on a NAO: an arm made limp leaves
    it awake; rest() ends it, wakeUp() brings it back."""
    assert motion.robotIsWakeUp()
    assert motion.getStiffnesses("Body") == [1.0] * 12
    motion.setStiffnesses("LArm", 0.0)
    time.sleep(0.05)
    assert motion.robotIsWakeUp()
    motion.rest()
    assert not motion.robotIsWakeUp()
    motion.wakeUp()
    assert motion.robotIsWakeUp()


def test_a_limp_joint_takes_a_command_but_does_not_move(
    sim: SimProcess, motion: Any
) -> None:
    """As NAOqi's guide says, at stiffness 0 any command is taken but the
    motor does not move: the command changes, the measured angle does not;
    stiffened, the joint goes to its command."""
    motion.setStiffnesses("LArm", 0.0)
    time.sleep(0.05)
    before = motion.getAngles("LShoulderPitch", True)[0]
    motion.angleInterpolation("LShoulderPitch", before - 0.3, 0.2, True)
    assert motion.getAngles("LShoulderPitch", False)[0] == pytest.approx(before - 0.3)
    assert motion.getAngles("LShoulderPitch", True)[0] == before
    motion.setStiffnesses("LArm", 1.0)
    time.sleep(0.2)
    assert motion.getAngles("LShoulderPitch", True)[0] == pytest.approx(before - 0.3)


def test_out_of_range_angles_are_refused_not_clamped(
    sim: SimProcess, motion: Any
) -> None:
    """RElbowRoll to 1.7 rad (range ends at 1.54462): error, logged, no motion."""
    motion.setStiffnesses("RArm", 1.0)
    time.sleep(0.1)
    before = motion.getAngles("RArm", True)
    with pytest.raises(
        RuntimeError, match=r"RElbowRoll key 1 = 1\.70000 rad is outside its range"
    ):
        motion.angleInterpolation(["RElbowRoll"], [[1.7]], [[1.0]], True)
    with pytest.raises(
        RuntimeError,
        match=r"RHand key 1 = 1\.50000 is outside its range \[0\.00000, 1\.00000\]",
    ):
        motion.setAngles("RHand", 1.5, 0.5)
    time.sleep(0.1)
    assert motion.getAngles("RArm", True) == before
    refused = [e for e in log_of(sim) if e["event"] == "refused"]
    assert "RElbowRoll key 1 = 1.70000 rad" in refused[-2]["reason"]


@pytest.mark.parametrize("method", ["angleInterpolationWithSpeed", "setAngles"])
def test_several_targets_for_one_joint_are_refused(
    sim: SimProcess, motion: Any, method: str
) -> None:
    """NAOqi takes one target per joint here. The sim took the last of
    [5.0, 1.0] and never checked 5.0 rad against the range; nested lists
    likewise. Now refused, naming the joint, and nothing moves."""
    motion.setStiffnesses("RArm", 1.0)
    time.sleep(0.1)
    before = motion.getAngles("RArm", False)
    call = getattr(motion, method)
    with pytest.raises(
        RuntimeError, match=f"RShoulderPitch has 2 target angles; {method} takes one"
    ):
        call("RShoulderPitch", [5.0, 1.0], 0.5)
    with pytest.raises(RuntimeError, match="RShoulderPitch has 2 target angles"):
        call(["RShoulderPitch", "RShoulderRoll"], [[0.3, 1.1], [-0.2, -0.3]], 0.5)
    time.sleep(0.1)
    assert motion.getAngles("RArm", False) == before


def test_over_speed_timing_is_refused(sim: SimProcess, motion: Any) -> None:
    """Keys too far apart for their time, or speed fractions above 1: errors."""
    motion.setStiffnesses("RArm", 1.0)
    start = motion.getAngles("RShoulderPitch", False)[0]
    with pytest.raises(
        RuntimeError, match=r"RShoulderPitch key 2 \(t = 0\.150 s\) needs"
    ):
        motion.angleInterpolation(
            "RShoulderPitch", [start, start - 1.0], [0.1, 0.15], True
        )
    with pytest.raises(RuntimeError, match=r"fractionMaxSpeed must be in \(0, 1\]"):
        motion.setAngles("RShoulderPitch", 0.0, 1.5)
    assert motion.getAngles("RShoulderPitch", False)[0] == start


def test_keys_are_followed_within_the_speed_limit(sim: SimProcess, motion: Any) -> None:
    """A blocking angleInterpolation lasts its keys' time; readings follow the
    smooth curve through the keys (the clamped cubic spline, at rest at
    both ends); the 20 ms cycle's logged states never exceed the speed
    limit."""
    motion.setStiffnesses("RArm", 1.0)
    time.sleep(0.05)
    q0 = motion.getAngles("RShoulderPitch", True)[0]
    keys, times = [q0 - 0.6, q0 - 0.2], [0.5, 1.0]
    sent = time.monotonic()
    future = motion.angleInterpolation("RShoulderPitch", keys, times, True, _async=True)
    readings = []
    while not future.isFinished():
        a = time.monotonic()
        value = motion.getAngles("RShoulderPitch", True)[0]
        b = time.monotonic()
        if b - a < 0.02:  # a reading this process was preempted around says little
            readings.append((0.5 * (a + b), value))
        time.sleep(0.01)
    assert not future.hasError()
    assert 0.98 < time.monotonic() - sent < 1.6  # blocks: the reply's trip is extra
    received = received_at(sim, "angleInterpolation")  # key times count from here
    assert 0.0 <= received - sent < 0.2
    done = [e for e in log_of(sim) if e["event"] == "done"][-1]
    assert done["method"] == "angleInterpolation"
    assert 1.0 <= sim_origin(sim) + done["t"] - received < 1.0 + 0.1  # keys' time
    t, measured = np.array(readings).T
    curve = CubicSpline([0.0, *times], [q0, *keys], bc_type="clamped")
    expected = curve(np.clip(t - received, 0.0, times[-1]))
    assert len(t) >= 5
    assert np.degrees(np.abs(measured - expected)).max() < 2.0
    states = [
        e
        for e in log_of(sim)
        if e["event"] == "state" and "RShoulderPitch" in e["positions"]
    ]
    stamps = np.array([e["t"] for e in states])
    angles = np.array([e["positions"]["RShoulderPitch"] for e in states])
    assert np.median(np.diff(stamps)) == pytest.approx(0.02, abs=0.004)
    assert np.max(np.abs(np.diff(angles)) / np.diff(stamps)) <= 8.26797 * 1.02


def test_set_angles_moves_at_the_fraction_of_its_speed(
    sim: SimProcess, motion: Any
) -> None:
    """setAngles returns at once; the joint moves at fraction x its speed limit."""
    motion.setStiffnesses("RArm", 1.0)
    time.sleep(0.05)
    q0 = motion.getAngles("RWristYaw", True)[0]
    began = time.monotonic()
    motion.setAngles("RWristYaw", q0 + 1.0, 0.1)
    assert time.monotonic() - began < 0.3  # the move takes 0.41 s: it did not wait
    time.sleep(0.2)
    a = time.monotonic()
    moved = motion.getAngles("RWristYaw", True)[0] - q0
    b = time.monotonic()
    received = received_at(sim, "setAngles")
    speed = 0.1 * 24.6229
    # read somewhere between a and b: at most 1 rad, at the speed since reception
    assert min(1.0, speed * (a - received)) - 1e-3 <= moved
    assert moved <= min(1.0, speed * (b - received)) + 1e-3
    assert moved > 0.1
    time.sleep(0.4)
    assert motion.getAngles("RWristYaw", True)[0] == pytest.approx(q0 + 1.0, abs=1e-9)


def test_limits_are_the_robot_descriptions(motion: Any) -> None:
    """getLimits gives [min, max, speed, torque] from the URDF."""
    limits = load_arm("left").limits
    got = np.array(motion.getLimits("LArm"))[:5]
    assert np.allclose(got[:, 0], limits.lower) and np.allclose(got[:, 1], limits.upper)
    assert np.allclose(got[:, 2], limits.velocity)


def test_killing_an_arms_tasks_stops_that_arm_only(
    sim: SimProcess, motion: Any
) -> None:
    """killTasksUsingResources("RArm") ends the right arm's move (its caller
    gets an error, the joint holds where it was) while the left arm's goes
    on to its last key."""
    motion.setStiffnesses(["RArm", "LArm"], 1.0)
    time.sleep(0.05)
    right0 = motion.getAngles("RElbowRoll", True)[0]
    left0 = motion.getAngles("LElbowRoll", True)[0]
    right = motion.angleInterpolation(
        "RElbowRoll", right0 + 0.6, 1.0, True, _async=True
    )
    left = motion.angleInterpolation("LElbowRoll", left0 - 0.6, 1.0, True, _async=True)
    time.sleep(0.4)
    motion.killTasksUsingResources(["RArm"])
    held = motion.getAngles("RElbowRoll", True)[0]
    assert right0 + 0.05 < held < right0 + 0.55  # stopped on its way
    right.wait(2000)
    assert right.hasError() and "killTasksUsingResources" in right.error()
    left.wait(2000)
    assert not left.hasError()
    assert motion.getAngles("LElbowRoll", True)[0] == pytest.approx(
        left0 - 0.6, abs=1e-3
    )
    time.sleep(0.1)
    assert motion.getAngles("RElbowRoll", True)[0] == pytest.approx(held, abs=1e-3)
    ended = [e for e in log_of(sim) if e["event"] in ("done", "interrupted")]
    killed, finished = ended[-2:]  # in the log's order: the kill came first
    assert killed["event"] == "interrupted" and killed["joints"] == ["RElbowRoll"]
    assert "killTasksUsingResources" in killed["reason"]
    assert finished["event"] == "done" and finished["joints"] == ["LElbowRoll"]


@pytest.mark.parametrize(
    ("call", "reason"),
    [
        (
            lambda m, now: m.angleInterpolation("RWristYaw", [now], [1e300], True),
            r"RWristYaw key 1 at t = 1e\+300 s is later than 86400 s \(a day\)",
        ),
        (
            lambda m, now: m.stiffnessInterpolation("RArm", 1.0, 1e300),
            r"RShoulderPitch key 1 at t = 1e\+300 s is later than 86400 s",
        ),
        (
            lambda m, now: m.angleInterpolationWithSpeed(
                "RWristYaw", now + (0.5 if now < 0.0 else -0.5), 1e-300
            ),
            r"RWristYaw key 1 at t = .* s is later than 86400 s",
        ),
        (
            lambda m, now: m.angleInterpolation(
                ["RWristYaw", "RWristYaw"], [[now], [now + 0.1]], [[1.0], [1.0]], True
            ),
            r"RWristYaw is named twice",
        ),
        (
            lambda m, now: m.stiffnessInterpolation(["RArm", "RHand"], 1.0, 0.5),
            r"RHand is named twice \(itself, or in a chain such as RArm\)",
        ),
    ],
)
def test_a_key_time_past_a_day_or_a_joint_named_twice_is_refused(
    sim: SimProcess, motion: Any, call: Any, reason: str
) -> None:
    """Refused at once with SimCommandError, nothing booked: the right arm
    is free after it. A key at 1e300 s used to fail the call with an
    OverflowError and keep RWristYaw (or the arm's stiffness) booked for
    good; a joint named twice was taken, and interrupted itself."""
    motion.setStiffnesses("RArm", 1.0)
    now = motion.getAngles("RWristYaw", False)[0]
    started = time.monotonic()
    with pytest.raises(RuntimeError, match=f"SimCommandError: {reason}"):
        call(motion, now)
    assert time.monotonic() - started < 1.0
    assert motion.areResourcesAvailable(["RArm"])
    refused = [e for e in log_of(sim) if e["event"] == "refused"]
    assert re.search(reason, refused[-1]["reason"])
    motion.angleInterpolation("RWristYaw", now + 0.05, 0.1, True)  # plays
