"""What the robot did, not what the bridge sent: its state before and after a call.

The bridge against the simulated NAO over real libqi, in this process, with
another libqi session playing the other party (the fall manager, a rest,
another Choregraphe client): an arm made limp mid-movement, a call the
robot ended early (raising, or returning as NAOqi's may), a robot not
awake, a robot whose own limits are narrower than the bridge's.
"""

from __future__ import annotations

import itertools
import math
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from bridge.almotion import AngleInterpolationCall
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_blend, minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.playback import play_and_sample
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.sim.joint import SAG_SPEED
from bridge.sim.joints import joint_specs
from bridge.sim.log import read_log
from shared.errors import (
    CallerDeadlineError,
    RobotBusyError,
    RobotCommandError,
    RobotLimitsError,
    RobotStateError,
)
from shared.libqi import qi
from shared.messages import Trajectory
from shared.robot import Side
from shared.robot.postures import forward, rest
from tests.narrowed_sim import narrowed_sim
from tests.slow_link import SlowLink


@pytest.fixture
def other(sim: SimProcess) -> Iterator[Any]:
    """ALMotion on a session of its own: another client of the robot."""
    with _motion(sim.url) as motion:
        yield motion


@contextmanager
def _motion(url: str) -> Iterator[Any]:
    session = qi.Session()
    session.connect(url)
    try:
        yield session.service("ALMotion")
    finally:
        session.close()


def _calls(log: Path | str, method: str) -> list[dict[str, Any]]:
    return [
        e for e in read_log(log) if e["event"] == "call" and e.get("method") == method
    ]


def test_an_arm_made_limp_mid_movement_is_an_error_and_not_snapped_back(
    sim: SimProcess, other: Any
) -> None:
    """Another client cuts the arm's stiffness during a reach: the reach was
    answered as played (64 degrees off, no error), and the next request
    stiffened the arm with its command 1.17 rad from where it hung, which
    snapped it back at the motor's top speed. Now the reach raises naming
    the arm, and the next request holds the arm where it is before
    stiffening it, then approaches from there: no joint moves faster than
    the approach's share of its limit."""
    bridge = RobotBridge(NaoqiClient(sim.url))
    reach = minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.5])
    back = minimum_jerk_trajectory("right", [forward("right"), rest("right")], [1.5])
    cut = threading.Timer(0.6, lambda: other.setStiffnesses("RArm", 0.0))
    cut.start()
    with pytest.raises(RobotStateError, match="stiffness of RArm dropped during"):
        bridge.execute(reach)
    cut.join()
    reply = bridge.execute(back)
    assert reply.approach_duration > 0.0
    assert sim.log_path is not None
    log = read_log(sim.log_path)
    limp_at = _calls(sim.log_path, "setStiffnesses")[-1]["t"]
    states = [e for e in log if e["event"] == "state" and e["t"] > limp_at]
    fastest = _fastest(states)
    limits = {j: s.velocity for j, s in joint_specs().items()}
    ratio = {j: v / limits[j] for j, v in fastest.items()}
    print("\nfastest share of the speed limit after the cut:", ratio)
    assert max(ratio.values()) < 0.3  # the approach's 25 %, not the motor's 100 %


@contextmanager
def _sagging(tmp_path: Path, sag: float) -> Iterator[SimProcess]:
    """A simulated NAO whose joints, let go, fall toward rest for ``sag`` [s]."""
    process = SimProcess(log_path=tmp_path / "sim.jsonl", limp_sag=sag)
    process.start()
    try:
        yield process
    finally:
        process.stop()


def test_a_limp_arm_still_falling_is_held_where_it_comes_to_rest(
    tmp_path: Path,
) -> None:
    """The arm let go at ``forward`` falls toward rest for 0.4 s at 1 rad/s
    (a NAO's for about 0.3 s); the next request read its posture once,
    mid-fall, and moved its command there: an angle the arm had already
    fallen past, to which stiffening then drove it back. Now the sensors
    are read until they hold still, and the command is held where the arm
    came to rest."""
    sag = 0.4
    a, b = np.array(forward("right")), np.array(rest("right"))
    with _sagging(tmp_path, sag) as sim, _motion(sim.url) as motion:
        bridge = RobotBridge(NaoqiClient(sim.url))
        bridge.execute(minimum_jerk_trajectory("right", [b, a], [1.0]))
        motion.setStiffnesses("RArm", 0.0)
        bridge.execute(minimum_jerk_trajectory("right", [a, b], [1.0]))
        assert sim.log_path is not None
        hold = _calls(sim.log_path, "angleInterpolation")[1]  # after the reach
    held = np.array(hold["angles"])[:, 0]
    came_to_rest = a + np.clip(b - a, -SAG_SPEED * sag, SAG_SPEED * sag)
    print("\nheld - where it came to rest [deg]:", np.degrees(held - came_to_rest))
    assert np.abs(held - came_to_rest).max() < math.radians(0.5)


def test_a_limp_arm_that_keeps_moving_is_busy(tmp_path: Path) -> None:
    """A limp arm that does not come to rest within a second (here it falls
    from raised for 2.6 s; or it is moved by hand) is busy: nothing is
    sent, neither a hold nor a stiffening."""
    raised = np.array(forward("right")) + np.array([-1.0, 0.0, 0.0, 0.0, 0.0])
    start = np.array(rest("right"))
    with _sagging(tmp_path, 3.0) as sim, _motion(sim.url) as motion:
        bridge = RobotBridge(NaoqiClient(sim.url))
        bridge.execute(minimum_jerk_trajectory("right", [start, raised], [1.5]))
        motion.setStiffnesses("RArm", 0.0)
        assert sim.log_path is not None
        before = len(read_log(sim.log_path))
        with pytest.raises(RobotBusyError, match=r"still moving \(limp, falling\?\)"):
            bridge.execute(minimum_jerk_trajectory("right", [raised, start], [1.0]))
        sent = [e for e in read_log(sim.log_path)[before:] if e["event"] == "call"]
    assert [e["method"] for e in sent] == []


def _narrow_shoulder(upper: float) -> dict[Side, FrameLimits]:
    """The bridge's limits with RShoulderPitch's upper limit at ``upper`` [rad]."""
    right = FrameLimits.for_arm("right")
    top = np.array(right.upper)
    top[0] = upper
    narrow = FrameLimits(
        right.names, right.lower, top, right.velocity, right.acceleration, right.jerk
    )
    return {Side.RIGHT: narrow, Side.LEFT: FrameLimits.for_arm("left")}


def test_a_limp_arm_resting_outside_the_bridge_range_is_left_limp(
    tmp_path: Path,
) -> None:
    """The arm let go at ``forward`` falls 0.4 rad to RShoulderPitch 0.4,
    past a bridge whose range ends at 0.3 (on a NAO a limp elbow may hang
    at its soft stop): the bridge held the command at 0.4, stiffened the
    arm there, then refused the approach's "frame 0" saying "nothing was
    sent". Now it refuses before sending anything, naming the joint, its
    angle and the range, and the arm stays limp where it hangs."""
    a, b = np.array(rest("right")), np.array(forward("right"))
    with _sagging(tmp_path, 0.4) as sim, _motion(sim.url) as motion:
        RobotBridge(NaoqiClient(sim.url)).execute(
            minimum_jerk_trajectory("right", [a, b], [1.0])
        )
        motion.setStiffnesses("RArm", 0.0)
        assert sim.log_path is not None
        before = len(read_log(sim.log_path))
        bridge = RobotBridge(NaoqiClient(sim.url), limits=_narrow_shoulder(0.3))
        with pytest.raises(RobotStateError) as caught:
            bridge.execute(minimum_jerk_trajectory("right", [b, b], [1.0]))
        sent = [e for e in read_log(sim.log_path)[before:] if e["event"] == "call"]
        stiffness = motion.getStiffnesses("RArm")[:5]
    message = caught.value.message
    print("\n", message)
    assert "RShoulderPitch is measured at angle 0.4000 rad" in message
    assert "outside the bridge's range [-2.0857, 0.3000] rad" in message
    assert "nothing was sent; the arm was left as it was (limp)" in message
    assert [e["method"] for e in sent if e["method"] != "setStiffnesses"] == []
    assert stiffness == [0.0] * 5


def test_a_refusal_after_a_limp_arm_was_held_says_what_was_sent(
    tmp_path: Path,
) -> None:
    """A limp arm is held where it hung and stiffened, then the caller's
    time left is found too short for the approach: the refusal said
    "nothing was sent" after two commands had gone out. Now it says the
    arm was held and stiffened, and that no movement was sent."""
    a, b = np.array(rest("right")), np.array(forward("right"))
    with _sagging(tmp_path, 0.4) as sim, _motion(sim.url) as motion:
        bridge = RobotBridge(NaoqiClient(sim.url))
        bridge.execute(minimum_jerk_trajectory("right", [a, b], [1.0]))
        motion.setStiffnesses("RArm", 0.0)
        back = minimum_jerk_trajectory("right", [a, b], [1.0])
        with pytest.raises(CallerDeadlineError) as caught:  # approach >= 0.5 s
            bridge.execute(back, until=time.monotonic() + 1.45)
        assert sim.log_path is not None
        methods = [e["method"] for e in read_log(sim.log_path) if e["event"] == "call"]
    outcome = caught.value.outcome
    assert caught.value.approach is not None and caught.value.approach >= 0.5
    assert methods[-2:] == ["angleInterpolation", "stiffnessInterpolation"]
    assert "nothing was sent" not in caught.value.message
    assert outcome.startswith("the limp arm's command was moved to where it hung")
    assert outcome.endswith("no movement was sent")


def test_an_arm_softened_but_not_let_go_is_not_an_error(
    sim: SimProcess, other: Any
) -> None:
    """Smart Stiffness (NAOqi's default) or a client holding the arm at 0.6
    leaves it stiff enough to follow: the reach was refused as "dropped"
    (checked against 0.999), as every movement on such a robot would be.
    Below 0.5 it is let go (the drop to 0 above is still an error)."""
    bridge = RobotBridge(NaoqiClient(sim.url))
    reach = minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.5])
    soften = threading.Timer(0.6, lambda: other.setStiffnesses("RArm", 0.6))
    soften.start()
    reply = bridge.execute(reach)
    soften.join()
    assert other.getStiffnesses("RArm")[:5] == pytest.approx([0.6] * 5)
    assert max(reply.report.tracking_max_deg.values()) < 2.0
    other.setStiffnesses("RArm", 0.4)
    back = minimum_jerk_trajectory("right", [forward("right"), rest("right")], [1.0])
    cut = threading.Timer(0.4, lambda: other.setStiffnesses("RArm", 0.4))
    cut.start()
    with pytest.raises(RobotStateError, match="stiffness of RArm dropped during"):
        bridge.execute(back)
    cut.join()


#: The width of the object in the ``gripping`` sim's hands (open fraction).
GRIP = 0.3


@pytest.fixture
def gripping(tmp_path: Path) -> Iterator[SimProcess]:
    """A simulated NAO whose hands hold an object ``GRIP`` wide."""
    process = SimProcess(log_path=tmp_path / "sim.jsonl", grip=GRIP)
    process.start()
    try:
        yield process
    finally:
        process.stop()


def _closed_hand(trajectory: Trajectory) -> Trajectory:
    """``trajectory`` with its hand commanded shut (0) throughout."""
    return trajectory.model_copy(
        update={
            "hand": [0.0] * len(trajectory.times),
            "hand_velocities": None,
            "hand_accelerations": None,
        }
    )


def test_an_approach_with_a_hand_closed_on_an_object_arrives(
    gripping: SimProcess,
) -> None:
    """The hand commanded shut reads the object's width (0.3, 17 "degrees"
    from its command): every approach of a pick and place failed "did not
    arrive" on RHand. The measured arrival is the arm's joints'."""
    bridge = RobotBridge(NaoqiClient(gripping.url))
    carry = _closed_hand(
        minimum_jerk_trajectory("right", [forward("right"), rest("right")], [1.0])
    )
    reply = bridge.execute(carry)
    assert reply.approach_duration > 0.0
    with _motion(gripping.url) as motion:
        assert motion.getAngles("RHand", True)[0] == pytest.approx(GRIP)
        assert motion.getAngles("RHand", False)[0] == pytest.approx(0.0, abs=1e-3)


def test_a_limp_arm_gripping_keeps_its_hand_command(gripping: SimProcess) -> None:
    """The arm let go while its hand, still stiff, holds an object: the
    hand's command (0, shut) was moved to its measured opening (0.3) before
    stiffening, so the grip would let go. Now a stiff hand is not held; its
    command stays shut."""
    bridge = RobotBridge(NaoqiClient(gripping.url))
    with _motion(gripping.url) as motion:
        motion.setStiffnesses(list(FrameLimits.for_arm("right").names), 0.0)
        time.sleep(0.1)  # one control cycle's ramp
        assert motion.getStiffnesses("RShoulderPitch")[0] == 0.0
        assert motion.getStiffnesses("RHand")[0] == 1.0
    assert gripping.log_path is not None
    cut = _calls(gripping.log_path, "setStiffnesses")[-1]["t"]
    reach = _closed_hand(
        minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.0])
    )
    bridge.execute(reach)
    for call in _calls(gripping.log_path, "angleInterpolation"):
        if call["t"] > cut and "RHand" in call["names"]:
            hand = call["angles"][call["names"].index("RHand")]
            assert max(hand) < 0.05, call


@pytest.mark.parametrize("let_go", ["RHand", "RArm"])
def test_a_limp_hand_is_held_where_it_sagged_not_snapped_back(
    tmp_path: Path, let_go: str
) -> None:
    """The hand held open (1.0) is let go (alone, or with its arm) and sags
    to 0.5; the next request stiffened it with its command still at 1.0,
    and it snapped back at its top speed (8.3 /s from standstill, over 1000
    /s^2) with "approach 0.0". Now a limp hand is held where it sagged like
    the arm, and the approach opens it again within the hand's limits."""
    start = np.array(forward("right"))
    still = minimum_jerk_trajectory("right", [start, start], [0.5])
    opened = still.model_copy(
        update={
            "hand": [1.0] * len(still.times),
            "hand_velocities": None,
            "hand_accelerations": None,
        }
    )
    samples: list[tuple[float, float]] = []
    with _sagging(tmp_path, 0.5) as sim, _motion(sim.url) as motion:
        bridge = RobotBridge(NaoqiClient(sim.url))
        bridge.execute(opened)
        motion.setStiffnesses(let_go, 0.0)
        time.sleep(0.7)  # sagged 0.5 s at 1 /s
        assert motion.getAngles("RHand", True)[0] == pytest.approx(0.5, abs=0.01)
        done = threading.Event()

        def sample() -> None:
            while not done.is_set():
                hand = motion.getAngles("RHand", True)[0]
                samples.append((time.monotonic(), hand))
                time.sleep(0.005)

        sampler = threading.Thread(target=sample)
        sampler.start()
        try:
            reply = bridge.execute(opened)
        finally:
            done.set()
            sampler.join()
        arrived = motion.getAngles("RHand", True)[0]
    t, hand = np.array(samples).T
    grid = np.arange(t[0], t[-1], 0.02)  # one control cycle
    speed = np.diff(np.interp(grid, t, hand)) / 0.02
    acceleration = np.diff(speed) / 0.02
    limits = FrameLimits.for_arm("right").with_hand("right")
    print(
        f"\nhand: fastest {np.abs(speed).max():.2f} /s (limit "
        f"{limits.velocity[-1]:.2f}), {np.abs(acceleration).max():.1f} /s^2 "
        f"(limit {limits.acceleration[-1]:.1f})"
    )
    assert reply.approach_duration > 0.0
    assert arrived == pytest.approx(1.0, abs=0.01)
    assert np.abs(speed).max() < 0.5 * limits.velocity[-1]
    assert np.abs(acceleration).max() < limits.acceleration[-1]


def test_a_connection_made_again_after_the_checks_sends_nothing(
    sim: SimProcess,
) -> None:
    """The command connection drops after the robot was checked (awake,
    limits), just before the frames go out: the client connected again
    silently and sent them on a connection never checked (perhaps another
    robot). Now the bridge refuses, and nothing of the trajectory goes out."""
    link = SlowLink(int(sim.url.rsplit(":", 1)[1]), 10e6)
    bridge = RobotBridge(NaoqiClient(link.url))
    hold = minimum_jerk_trajectory("right", [rest("right"), rest("right")], [0.5])

    def drop(_: Any) -> None:
        link.cut(0)  # the command connection, the first made
        for _ in range(200):
            if not bridge.client.connected:
                return
            time.sleep(0.01)

    try:
        with pytest.raises(RobotStateError, match="connection to the robot was made"):
            bridge.execute(hold, on_play=drop)
    finally:
        link.close()
    assert link.connections >= 2
    assert sim.log_path is not None
    assert _calls(sim.log_path, "angleInterpolation") == []


def _fastest(states: list[dict[str, Any]]) -> dict[str, float]:
    """Each joint's fastest speed between consecutive logged cycles [rad/s]."""
    fastest: dict[str, float] = {}
    for a, b in itertools.pairwise(states):
        dt = b["t"] - a["t"]
        for joint in set(a["positions"]) & set(b["positions"]):
            speed = abs(b["positions"][joint] - a["positions"][joint]) / dt
            fastest[joint] = max(fastest.get(joint, 0.0), speed)
    return fastest


@pytest.fixture
def quiet_kills(tmp_path: Path) -> Iterator[SimProcess]:
    """A simulated NAO whose killed blocking calls return, as NAOqi's may."""
    process = SimProcess(log_path=tmp_path / "sim.jsonl", killed_calls_return=True)
    process.start()
    try:
        yield process
    finally:
        process.stop()


def test_a_killed_call_returns_normally_on_the_sim_so_told(
    quiet_kills: SimProcess,
) -> None:
    """With ``killed_calls_return`` a killed angleInterpolation answers
    without error (the stock sim raises "was interrupted")."""
    with _motion(quiet_kills.url) as motion:
        motion.wakeUp()
        start = motion.getAngles("RShoulderPitch", False)[0]
        future = motion.angleInterpolation(
            "RShoulderPitch", start - 0.5, 2.0, True, _async=True
        )
        kill = threading.Timer(0.3, motion.killAll)
        kill.start()
        future.wait(5000)
        kill.join()  # done on the open session, never after it closed
        assert future.isFinished() and not future.hasError()


def test_a_movement_the_robot_ends_early_is_an_error(
    quiet_kills: SimProcess,
) -> None:
    """killAll 0.8 s into a 2 s reach, the call returning normally: it was
    reported as a clean execution. Now it raises, saying when it ended."""
    bridge = RobotBridge(NaoqiClient(quiet_kills.url))
    with _motion(quiet_kills.url) as motion:
        reach = minimum_jerk_trajectory(
            "right", [rest("right"), forward("right")], [2.0]
        )
        kill = threading.Timer(0.8, motion.killAll)
        kill.start()
        with pytest.raises(RobotStateError) as caught:
            bridge.execute(reach)
        kill.join()
    assert "the robot ended the movement at t = " in caught.value.message
    assert "of 2.00 s" in caught.value.message


def test_a_movement_killed_near_its_end_after_a_slow_arrival_is_an_error(
    quiet_kills: SimProcess,
) -> None:
    """A 3 s call at 500 fps carried at 500 kB/s reaches the robot ~0.4 s
    after it left; killed 0.25 s before its last key (robot time: when its
    commanded RShoulderPitch passes that point), it returned normally, and
    counted from when it left it seemed to have played its whole length: a
    clean execution. Counted from its arrival mark it ended early."""
    link = SlowLink(int(quiet_kills.url.rsplit(":", 1)[1]), 500e3)
    a, b = np.array(forward("right")), np.array(rest("right"))
    last, before_end = 1.0, 0.25
    threshold = a[0] + float(
        minimum_jerk_blend(np.array([(last - before_end) / last]))[0]
    ) * (b[0] - a[0])
    trajectory = minimum_jerk_trajectory("right", [b, a, b], [2.0, last])
    done = threading.Event()
    try:
        with _motion(quiet_kills.url) as motion:

            def kill_near_the_end() -> None:
                there = False  # at forward, on the way back next
                while not done.wait(0.002):
                    q = motion.getAngles("RShoulderPitch", False)[0]
                    there = there or abs(q - a[0]) < 0.01
                    if there and (b[0] - a[0]) * (q - threshold) >= 0:
                        motion.killTasksUsingResources(["RArm"])
                        return

            watcher = threading.Thread(target=kill_near_the_end)
            watcher.start()
            try:
                with pytest.raises(RobotStateError) as caught:
                    RobotBridge(NaoqiClient(link.url)).execute(trajectory, rate=500.0)
            finally:
                done.set()
                watcher.join()
    finally:
        link.close()
    print("\n", caught.value.message, f"({link.carried} bytes carried)")
    assert "the robot ended the movement at t = " in caught.value.message
    assert link.carried > 150e3  # the call took ~0.3 s or more to arrive


@pytest.mark.parametrize("returns", [False, True], ids=["raising", "returning"])
@pytest.mark.parametrize("act", ["rest", "killAll"])
def test_a_movement_another_client_ends_is_robot_state_saying_if_limp(
    tmp_path: Path, returns: bool, act: str
) -> None:
    """rest() or killAll() from another client 0.8 s into a 2 s reach. A
    killed call that raised (the stock sim) was robot_command_refused, "the
    robot refused angleInterpolation", though it had played; one that
    returned was robot_state "the arm stopped where it was then" after
    rest() had left every joint at stiffness 0. Now both are robot_state,
    saying how far the reach played and, after rest(), that the arm is
    limp."""
    process = SimProcess(log_path=tmp_path / "sim.jsonl", killed_calls_return=returns)
    process.start()
    try:
        with _motion(process.url) as motion:
            bridge = RobotBridge(NaoqiClient(process.url))
            reach = minimum_jerk_trajectory(
                "right", [rest("right"), forward("right")], [2.0]
            )
            cut = threading.Timer(0.8, getattr(motion, act))
            cut.start()
            with pytest.raises(RobotStateError) as caught:
                bridge.execute(reach)
            cut.join()
    finally:
        process.stop()
    message = caught.value.message
    print("\n", message)
    played = float(message.split("ended the movement at t = ")[1].split(" s ")[0])
    assert 0.0 < played < 1.9
    assert "of 2.00 s" in message
    assert ("interrupted: killAll" in message) != returns
    limp = "and is limp (RShoulderPitch stiffness 0.00)"
    assert (limp in message) == (act == "rest")


def test_a_call_the_robot_refuses_is_still_refused(sim: SimProcess) -> None:
    """A call the robot checks and refuses moves nothing: it stays
    robot_command_refused, though a large one (5000 keys) is refused
    0.04-0.06 s after its arrival mark is answered on the sim (a killed
    call is told apart by its command having moved, not by the time)."""
    client = NaoqiClient(sim.url)
    names = list(FrameLimits.for_arm("right").names)
    start = client.get_angles(names, use_sensors=False)
    for keys in (50, 5000):
        angles = [[float(a)] * keys for a in start]
        angles[0][-1] = 5.0  # RShoulderPitch past its stop at the last key
        times = [[0.02 * (k + 1) for k in range(keys)]] * len(names)
        call = AngleInterpolationCall(names, angles, times)
        with pytest.raises(RobotCommandError, match="refused angleInterpolation"):
            play_and_sample(client, call)
        assert client.get_angles(names, use_sensors=False) == pytest.approx(start)


def test_an_approach_the_robot_cuts_short_sends_no_trajectory(
    quiet_kills: SimProcess,
) -> None:
    """The approach's task killed half-way, its call returning normally:
    the trajectory went out from where the arm had stopped (its first key
    four times the speed limit away; only the sim's refusal stopped it).
    Now the bridge raises and sends nothing after the approach, and says
    it ended the approach (it said "the movement", as of the trajectory)."""
    bridge = RobotBridge(NaoqiClient(quiet_kills.url))
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [1.5]
    )
    with _motion(quiet_kills.url) as motion:
        kill = threading.Timer(0.5, motion.killTasksUsingResources, [["RArm"]])
        kill.start()
        with pytest.raises(RobotStateError) as caught:
            bridge.execute(trajectory)
        kill.join()
    print(f"\n{caught.value.message}")
    assert "the robot ended the approach at t = " in caught.value.message
    assert "nothing of the trajectory was sent" in caught.value.message
    assert caught.value.stopped and caught.value.evidence["phase"] == "approach"
    assert quiet_kills.log_path is not None
    assert len(_calls(quiet_kills.log_path, "angleInterpolation")) == 1
    assert not [e for e in read_log(quiet_kills.log_path) if e["event"] == "refused"]


def test_a_robot_not_awake_is_refused_unless_allowed(
    sim: SimProcess, other: Any
) -> None:
    """After rest() the bridge stiffened the arm alone and played the reach
    on a resting robot. Now it refuses before sending anything; a bridge
    told it may (``--allow-not-awake``) plays."""
    other.rest()
    assert not other.robotIsWakeUp()
    assert sim.log_path is not None
    before = len(read_log(sim.log_path))
    reach = minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.0])
    with pytest.raises(RobotStateError, match=r"robotIsWakeUp\(\) is false"):
        RobotBridge(NaoqiClient(sim.url)).execute(reach)
    sent = [e for e in read_log(sim.log_path)[before:] if e["event"] == "call"]
    assert sent == []
    reply = RobotBridge(NaoqiClient(sim.url), require_awake=False).execute(reach)
    assert reply.frames > 0


@pytest.fixture
def narrow_sim() -> Iterator[str]:
    """A simulated robot whose RShoulderRoll stops at -0.0087 rad (a Pepper's)."""
    upper = joint_specs()["RShoulderRoll"].upper
    with narrowed_sim("RShoulderRoll", "upper", upper + 0.0087) as url:
        yield url


def test_a_robot_with_narrower_limits_is_refused(narrow_sim: str) -> None:
    """A robot whose RShoulderRoll range ends at -0.0087 rad (the bridge's at
    0.314) was sent NAO ranges unasked. Now its getLimits is read and the
    bridge refuses, naming the joint, before sending anything."""
    reach = minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.0])
    with pytest.raises(RobotLimitsError) as caught:
        RobotBridge(NaoqiClient(narrow_sim)).execute(reach)
    error = caught.value
    assert (error.joint, error.quantity) == ("RShoulderRoll", "upper")
    assert error.robot == pytest.approx(-0.0087)
    assert error.bridge == pytest.approx(0.314159)
    with _motion(narrow_sim) as motion:
        assert np.allclose(
            motion.getAngles("RArm", False)[:5], rest("right"), atol=1e-9
        )


@pytest.mark.parametrize(
    ("joint", "quantity"), [("RElbowRoll", "upper"), ("RElbowYaw", "velocity")]
)
def test_a_robot_narrower_by_more_than_rounding_is_refused(
    joint: str, quantity: str
) -> None:
    """A robot whose RElbowRoll stops 9e-5 rad short of the bridge's 1.54462
    (or whose RElbowYaw is 9e-5 rad/s slower) passed the check's fixed 1e-4
    slack, and the robot refused the bridge's key at 1.54462. Now only
    rounding passes: 1e-6 less (the description's 6 digits, NAOqi's single
    precision) plays; 9e-5 less is refused, naming the joint."""
    reach = minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.0])
    with narrowed_sim(joint, quantity, 1e-6) as url:
        assert RobotBridge(NaoqiClient(url)).execute(reach).frames > 0
    with (
        narrowed_sim(joint, quantity, 9e-5) as url,
        pytest.raises(RobotLimitsError) as caught,
    ):
        RobotBridge(NaoqiClient(url)).execute(reach)
    error = caught.value
    assert (error.joint, error.quantity) == (joint, quantity)
    assert error.bridge - error.robot == pytest.approx(9e-5, rel=1e-3)
