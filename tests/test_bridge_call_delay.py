"""A movement whose call takes long to reach the robot is not started for a
caller who will not wait for it to end.

The bridge counted the trajectory's length alone against the caller's time
left: an 8 s trajectory at 500 fps over a slow link played in full while
its caller had given up (the call arrived 0.6 s late). It now counts the
call's way, as measured on the calls before, and the answer's making.
Real parts: the simulated NAO over libqi behind a bandwidth-limited relay.
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from bridge.in_time import AFTER, LEARN_FROM_KEYS, CallDelay
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.errors import CallerDeadlineError
from shared.robot.postures import rest
from tests.slow_link import SlowLink

AWAY = rest("right") + np.array([-0.5, -0.2, 0.4, 0.4, 0.3])
#: Frame rate of the large calls [Hz]: 1000 frames in 2 s.
RATE = 500.0
#: The relay's bandwidth [B/s]: a 2 s call at RATE takes about 0.5 s.
BANDWIDTH = 250e3


def _calls(sim: SimProcess) -> int:
    assert sim.log_path is not None
    return sum(e["event"] == "motion" for e in read_log(sim.log_path))


def test_a_call_slow_to_arrive_is_counted_against_the_caller(sim: SimProcess) -> None:
    """After one large call has shown the link's speed, a caller who waits
    the trajectory's length + 0.2 s is refused, nothing sent, the refusal
    naming the time counted for the call; given time, it plays."""
    link = SlowLink(int(sim.url.rsplit(":", 1)[1]), BANDWIDTH)
    robot = RobotBridge(NaoqiClient(link.url))
    there = minimum_jerk_trajectory("right", [rest("right"), AWAY], [2.0])
    back = minimum_jerk_trajectory("right", [AWAY, rest("right")], [2.0])
    try:
        first = robot.execute(there, rate=RATE)
        played = _calls(sim)
        with pytest.raises(CallerDeadlineError) as caught:
            robot.execute(back, rate=RATE, until=time.monotonic() + 2.0 + 0.2)
        refused = _calls(sim)
        again = robot.execute(back, rate=RATE, until=time.monotonic() + 30.0)
    finally:
        robot.client.close()
        link.close()
    print(
        f"\nfirst call's start delay {first.report.start_delay:.3f} s; {caught.value}"
    )
    assert first.report.start_delay > 0.3  # the link is slow
    assert refused == played  # nothing sent for the refused caller
    assert caught.value.overhead >= first.report.start_delay * 0.8
    assert "for the call's way and the answer" in caught.value.message
    assert again.frames == first.frames


def test_the_delay_is_latency_plus_size() -> None:
    """Small calls teach the latency, large ones the time per key beyond it:
    an 8 s trajectory at 25 fps (1000 keys, 7 ms) taught 7 us per key, and
    a 500 fps call's delay was over-estimated 1.7 times."""
    delay = CallDelay()
    assert delay.estimate(40_000) == 0.0  # nothing seen: nothing counted
    delay.learn(1000, 0.007)  # latency
    assert delay.estimate(40_000) == pytest.approx(0.007)
    delay.learn(LEARN_FROM_KEYS * 4, 0.007 + 0.2)
    assert delay.estimate(LEARN_FROM_KEYS * 8) == pytest.approx(0.007 + 0.4)
    delay.learn(50, 0.003)  # a lower latency
    assert delay.estimate(0) == pytest.approx(0.003)
    assert AFTER > 0.0


def test_a_slow_frames_callback_is_counted_against_the_caller(sim: SimProcess) -> None:
    """``on_play`` publishes the frames on the bus, where a put waits for
    room up to 5 s when a subscriber stopped reading (``Bus.publish``'s
    BLOCK). The caller's time was checked before it only: a trajectory
    then played past the caller's deadline. It is checked after it too."""
    robot = RobotBridge(NaoqiClient(sim.url))
    there = minimum_jerk_trajectory("right", [rest("right"), AWAY], [1.0])
    robot.execute(there, approach=True)  # at the start: no approach below
    back = minimum_jerk_trajectory("right", [AWAY, rest("right")], [1.0])
    played = _calls(sim)
    with pytest.raises(CallerDeadlineError):
        robot.execute(
            back,
            on_play=lambda frames: time.sleep(3.0),
            until=time.monotonic() + 1.0 + 2.0,
        )
    assert _calls(sim) == played  # nothing of the trajectory sent
