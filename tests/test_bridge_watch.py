"""The bridge watches a movement on a connection of its own, and gives up on a
robot only when it must, asking it to stop first.

The bridge (``python -m bridge``, or :class:`RobotBridge` in this process
where a test must act at the moment the call leaves) reaches the simulated
NAO process over real libqi through :class:`~tests.slow_link.SlowLink`, a
loopback relay that carries a limited bandwidth toward the robot and can
go silent. The readings used to share the call's connection and waited
until the whole call had arrived: a call that took over a second to arrive
was declared lost ("no answer to getAngles") while the robot, fine, was
about to play it, unwatched.
"""

from __future__ import annotations

import contextlib
import math
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.playback import HALT_WAIT, LOST_AFTER, OVERRUN, overdue
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.errors import RobotUnavailableError
from shared.messages import CommandFrames, ExecuteReply, ExecuteRequest, Trajectory
from shared.robot.postures import rest
from tests.slow_link import SlowLink
from tests.test_bridge import BridgeProcess

#: A posture inside every range, away from rest [rad].
AWAY = rest("right") + np.array([-0.5, -0.2, 0.4, 0.4, 0.3])
#: Frame rate of the large calls [Hz]: 130 kB a second of movement to carry.
RATE = 1000.0
#: Fast enough that a call arrives at once [B/s].
FAST = 50e6


def reach(duration: float) -> Trajectory:
    """Rest to ``AWAY`` in ``duration`` [s], minimum jerk."""
    return minimum_jerk_trajectory("right", [rest("right"), AWAY], [duration])


def link_to(sim: SimProcess, bandwidth: float) -> SlowLink:
    return SlowLink(int(sim.url.rsplit(":", 1)[1]), bandwidth)


@pytest.fixture
def fast_link(sim: SimProcess) -> Iterator[SlowLink]:
    relay = link_to(sim, FAST)
    try:
        yield relay
    finally:
        relay.close()


def sim_events(sim: SimProcess, *events: str) -> list[dict[str, Any]]:
    """The sim's log entries of these kinds, each with ``at``: its monotonic
    time in this process [s] (the sim logs its clock's origin)."""
    assert sim.log_path is not None
    log = read_log(sim.log_path)
    origin = log[0]["origin"]
    return [dict(e, at=origin + e["t"]) for e in log if e["event"] in events]


def when_sim_logs(sim: SimProcess, event: str, method: str) -> float:
    """Wait (at most 10 s) for the sim's first ``event`` of ``method``."""
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        found = [e for e in sim_events(sim, event) if e.get("method") == method]
        if found:
            return float(found[0]["at"])
        time.sleep(0.01)
    raise AssertionError(f"the sim logged no {event} of {method}")


def last_moved(sim: SimProcess) -> float:
    """When the sim last logged a moving joint [s, this process's clock]
    (-inf: never): a ``state`` line with a joint not where its previous line
    had it. The cycle after a kill logs the stopped joints once more, held
    (``bridge.sim.log``): no movement, though a cycle after the kill."""
    last, where = -math.inf, {}
    for entry in sim_events(sim, "state"):
        positions = entry["positions"]
        if any(where.get(joint) != q for joint, q in positions.items()):
            last = float(entry["at"])
        where.update(positions)
    return last


def test_the_line_holding_a_killed_joint_is_no_movement(tmp_path: Path) -> None:
    """A joint killed mid-move last moved at the kill's ``state`` line, not
    at the next cycle's, which logs it held where it stopped."""
    with SimProcess(log_path=tmp_path / "sim.jsonl", period=0.1) as sim:
        client = NaoqiClient(sim.url)
        try:
            start = float(client.call("getAngles", ["RShoulderPitch"], True)[0])
            args = (["RShoulderPitch"], [[start - 1.0]], [[2.0]], True)
            moving = threading.Thread(target=_move, args=(client, *args))
            moving.start()
            time.sleep(0.35)
            client.call("killTasksUsingResources", ["RArm"], timeout=5.0)
            moving.join(5.0)
            time.sleep(0.35)  # three cycles: the held line is logged
        finally:
            client.close()
        states = sim_events(sim, "state")
        stopped = [float(e["at"]) for e in states if "stopped" in e]
        assert len(stopped) == 1
        assert max(float(e["at"]) for e in states) > stopped[0]  # the held line
        assert last_moved(sim) == stopped[0]


def _move(client: NaoqiClient, *args: object) -> None:
    """``angleInterpolation(*args)``; the kill makes it fail, as it should."""
    with contextlib.suppress(Exception):  # the interrupted call's error
        client.call("angleInterpolation", *args, timeout=5.0)


def finished(sim: SimProcess) -> list[str]:
    """The angleInterpolation calls the sim saw through to their last key."""
    return [
        e["event"]
        for e in sim_events(sim, "done")
        if e["method"] == "angleInterpolation"
    ]


def after_the_call_leaves(action: Any) -> Any:
    """An ``on_play`` callback that runs ``action`` on a thread."""

    def on_play(_: CommandFrames) -> None:
        threading.Thread(target=action, daemon=True).start()

    return on_play


def test_a_call_slow_to_arrive_is_watched_to_its_end(sim: SimProcess) -> None:
    """1000 frames (130 kB) over a 100 kB/s link reach the robot 1.3 s after
    they leave: the bridge reads the angles on a second connection all the
    while and reports the movement, tracked within 1 degree RMS from its
    measured start. It used to give up after 1 s ("no answer to getAngles")
    while the robot went on to play the call unwatched."""
    link = link_to(sim, 100e3)
    bridge = BridgeProcess(link.url)
    try:
        reply = bridge.execute(ExecuteRequest(trajectory=reach(1.0), rate=RATE))
    finally:
        bridge.close()
        link.close()
    assert "error" not in reply, reply
    done = ExecuteReply.model_validate(reply)
    report = done.report
    print(
        f"\n{done.frames} frames, {link.carried} bytes toward the robot over "
        f"{link.connections} connections; start delay {report.start_delay:.3f} s, "
        f"{len(done.states.times)} readings, largest gap "
        f"{np.diff(done.states.times).max() * 1000:.0f} ms"
    )
    assert done.frames == 1000 and link.connections == 2
    assert report.start_delay > LOST_AFTER
    assert np.diff(done.states.times).max() < LOST_AFTER / 2
    assert max(report.tracking_rms_deg.values()) < 1.0
    assert not sim_events(sim, "refused", "interrupted")
    assert not [
        e for e in sim_events(sim, "call") if e["method"] == "killTasksUsingResources"
    ]


def test_a_link_gone_silent_while_the_call_is_on_its_way_is_lost_in_time(
    sim: SimProcess,
) -> None:
    """The link goes silent 0.3 s after a call that needs 1.4 s to arrive
    left: robot_unavailable within LOST_AFTER + HALT_WAIT (+ 0.2 s) of the
    silence, naming the readings; the stop sent does not get through, and
    the bridge says it goes on stopping the arm, should the link come back."""
    link = link_to(sim, 100e3)
    frozen: list[float] = []

    def freeze() -> None:
        time.sleep(0.3)
        frozen.append(time.monotonic())
        link.freeze()

    robot = RobotBridge(NaoqiClient(link.url))
    try:
        with pytest.raises(RobotUnavailableError) as lost:
            robot.execute(reach(1.0), rate=RATE, on_play=after_the_call_leaves(freeze))
        delay = time.monotonic() - frozen[0]
    finally:
        robot.client.close()
        link.close()
    print(f"\nlost {delay * 1000:.0f} ms after the link went silent: {lost.value}")
    assert "no answer to getAngles" in lost.value.reason
    assert "ALMotion.killTasksUsingResources sent, not answered" in lost.value.reason
    assert "a stop follows the call still on its way" in lost.value.reason
    assert LOST_AFTER < delay < LOST_AFTER + HALT_WAIT + 0.2


def test_a_robot_whose_readings_go_silent_is_stopped(
    sim: SimProcess, fast_link: SlowLink
) -> None:
    """The readings' connection stops answering 0.3 s into a 2 s movement:
    the robot is lost after LOST_AFTER, and the stop sent on the call's
    connection, which still answers, stops the arm mid-movement, so it does
    not go on moving unwatched."""
    robot = RobotBridge(NaoqiClient(fast_link.url))

    def silence() -> None:
        time.sleep(0.3)
        fast_link.hold_answers(1)  # the second connection: the readings'

    try:
        with pytest.raises(RobotUnavailableError) as lost:
            robot.execute(reach(2.0), rate=25.0, on_play=after_the_call_leaves(silence))
    finally:
        robot.client.close()
    print(f"\n{lost.value}")
    assert "no answer to getAngles" in lost.value.reason
    assert (
        "stopped it (ALMotion.killTasksUsingResources answered, the call ended)"
        in lost.value.reason
    )
    began = when_sim_logs(sim, "motion", "angleInterpolation")
    kill = when_sim_logs(sim, "call", "killTasksUsingResources")
    time.sleep(2.0 - (time.monotonic() - began))  # the movement's end, unstopped
    assert LOST_AFTER < kill - began < 2.0
    assert last_moved(sim) < kill + 0.05
    assert finished(sim) == []


def test_a_robot_whose_call_connection_drops_is_stopped(
    sim: SimProcess, fast_link: SlowLink
) -> None:
    """The call's connection is cut 0.3 s into a 2 s movement: the robot,
    which plays on, is lost at once and stopped on the readings' connection."""
    robot = RobotBridge(NaoqiClient(fast_link.url))

    def cut() -> None:
        time.sleep(0.3)
        fast_link.cut(0)  # the first connection: the call's

    try:
        with pytest.raises(RobotUnavailableError) as lost:
            robot.execute(reach(2.0), rate=25.0, on_play=after_the_call_leaves(cut))
    finally:
        robot.client.close()
    print(f"\n{lost.value}")
    assert (
        "ALMotion.killTasksUsingResources answered; the call's connection dropped: "
        "the bridge keeps stopping the arm for 1 s" in lost.value.reason
    )
    began = when_sim_logs(sim, "motion", "angleInterpolation")
    kill = when_sim_logs(sim, "call", "killTasksUsingResources")
    time.sleep(2.0 - (time.monotonic() - began))  # the movement's end, unstopped
    assert kill - began < 0.6
    assert last_moved(sim) < kill + 0.05
    assert finished(sim) == []


def test_a_movement_that_overruns_is_caught_and_stopped(
    sim: SimProcess, fast_link: SlowLink
) -> None:
    """The call's answer never comes back (its connection's answers are held
    once the call has reached the robot) while the readings flow: the bridge
    gives up OVERRUN after the last key, counted from the call's arrival,
    and asks the robot to stop on the readings' connection."""
    robot = RobotBridge(NaoqiClient(fast_link.url))
    duration = 0.5

    def hold_the_answer() -> None:
        when_sim_logs(sim, "motion", "angleInterpolation")
        time.sleep(0.1)  # the arrival mark's answer is back by now
        fast_link.hold_answers(0)  # the first connection: the call's

    try:
        with pytest.raises(RobotUnavailableError) as lost:
            robot.execute(
                reach(duration),
                rate=25.0,
                on_play=after_the_call_leaves(hold_the_answer),
            )
        given_up = time.monotonic()
    finally:
        robot.client.close()
    print(f"\n{lost.value}")
    assert "did not end 1 s after its last key" in lost.value.reason
    assert (
        "ALMotion.killTasksUsingResources answered; the bridge keeps stopping the "
        "arm until the call ends" in lost.value.reason
    )
    began = when_sim_logs(sim, "motion", "angleInterpolation")
    kill = when_sim_logs(sim, "call", "killTasksUsingResources")
    assert duration + OVERRUN < kill - began < duration + OVERRUN + 0.3
    assert kill < given_up


def test_a_call_whose_arrival_mark_is_answered_late_is_played_not_ended_early(
    sim: SimProcess, fast_link: SlowLink
) -> None:
    """The call's connection carries no answer for its first second (as when
    another client's blocking calls hold the robot's worker threads: the
    mark came 0.87 s late), so its arrival mark is answered then, while the
    robot plays the whole 2 s call: the bridge said "the robot ended the
    movement at t = 1.0 s of 2.0 s (its call returned before its last key:
    its motion task was killed ...)". A call that returned its duration
    after it left, its joints commanded at its last key, played through."""
    robot = RobotBridge(NaoqiClient(fast_link.url))
    trajectory = reach(2.0)

    def hold_the_mark(_: CommandFrames) -> None:
        fast_link.hold_answers(0)  # the first connection: the call's
        threading.Timer(1.0, fast_link.release_answers, (0,)).start()

    try:
        reply = robot.execute(trajectory, rate=25.0, on_play=hold_the_mark)
    finally:
        robot.client.close()
    worst = max(reply.report.tracking_rms_deg.values())
    print(f"\nplayed; worst joint RMS {worst:.3f} deg")
    assert finished(sim) != []  # the sim played it to its last key


def test_a_call_given_up_on_its_way_is_ended_as_it_takes_effect(
    sim: SimProcess,
) -> None:
    """4000 frames (520 kB) over an 80 kB/s link take 6.5 s to arrive, longer
    than the call's duration + OVERRUN (5 s): the bridge gives up. One stop
    sent behind the call was served while the robot still checked the call,
    which then played its whole 4 s unwatched (5 times in 5); the bridge now
    stops the arm every control cycle from the call's arrival until the
    call has ended: it moves a few control cycles at most. The stops end
    with the call, and the bridge, which took no movement meanwhile, then
    plays the next one."""
    link = link_to(sim, 80e3)
    robot = RobotBridge(NaoqiClient(link.url))
    try:
        with pytest.raises(RobotUnavailableError) as lost:
            robot.execute(reach(4.0), rate=RATE)
        with pytest.raises(RobotUnavailableError) as meanwhile:
            robot.execute(reach(0.5), rate=25.0)
        began = when_sim_logs(sim, "call", "angleInterpolation")  # keys count
        ended = _when_no_longer_stopping(robot.client, 10.0)
        time.sleep(0.3)
        moved, kills = last_moved(sim), _kills(sim)
        played = finished(sim)
        again = robot.execute(reach(0.5), rate=25.0)
    finally:
        robot.client.close()
        link.close()
    print(
        f"\n{lost.value}\nkills after the call took effect [ms]: "
        f"{[round((k - began) * 1000) for k in kills if k >= began]}; last moved "
        f"{(moved - began) * 1000:.0f} ms after it; stops ended "
        f"{(ended - began) * 1000:.0f} ms after it"
    )
    assert "did not reach the robot within 5.00 s" in lost.value.reason
    assert (
        "a stop follows the call still on its way; the bridge keeps stopping the "
        "arm until it ends" in lost.value.reason
    )
    assert "still stopping the arm" in meanwhile.value.reason
    assert [k for k in kills if began <= k < began + 0.1]
    assert moved < began + 0.1
    assert played == []
    assert max(kills) < ended
    assert again.frames == 13 and max(again.report.tracking_rms_deg.values()) < 1.0


def _kills(sim: SimProcess) -> list[float]:
    """When the sim served each stop [s, this process's clock]."""
    return [
        e["at"]
        for e in sim_events(sim, "call")
        if e["method"] == "killTasksUsingResources"
    ]


def _when_no_longer_stopping(client: NaoqiClient, timeout: float) -> float:
    """Wait (at most ``timeout`` [s]) until ``client`` takes movements again."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            client.refuse_while_stopping()
            return time.monotonic()
        except RobotUnavailableError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.005)


@pytest.mark.parametrize(
    ("arrival", "now", "why"),
    [
        (None, 2.9, None),
        (None, 3.1, "did not reach the robot within 3.00 s of leaving"),
        (2.5, 5.4, None),
        (2.5, 5.6, "did not end 1 s after its last key"),
    ],
)
def test_a_call_is_overdue_counted_from_its_arrival(
    arrival: float | None, now: float, why: str | None
) -> None:
    """A 2 s call that left at 0: due at the robot by 3 s, and to end by
    3 s after it arrived (arrived at 2.5 s: by 5.5 s, not 3 s)."""
    problem = overdue(0.0, arrival, 2.0, now)
    if why is None:
        assert problem is None
    else:
        assert problem is not None and why in problem
