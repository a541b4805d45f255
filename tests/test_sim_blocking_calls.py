"""Blocking calls in flight hold no thread of the simulated NAO's: a stop from
another client takes effect at once, as on a NAO.

The sim once answered a blocking call from a libqi worker thread that waited
for its task to end. Four such calls in flight (one per client) held the
pool's threads, and a fifth client's ``killTasksUsingResources`` waited
until libqi found the pool stuck and added a thread: it took effect 0.5 s
after it was sent (0.1 to 0.9 s with three to eight calls in flight).
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import qi

from bridge.sim import SimProcess
from bridge.sim.log import read_log

#: One joint per client, two on each arm, each moved by a blocking call.
JOINTS = ["LShoulderPitch", "RShoulderPitch", "LElbowYaw", "RElbowYaw"]
#: Each call's duration [s]: far longer than the stop may take.
DURATION = 3.0
#: Longest a stop may take to act once sent [s], on this machine's monotonic
#: clock, which the sim's log shares: three control cycles. The sim acts on
#: a stop as it arrives (its cycle holds the joints' lock well under 1 ms of
#: every 20 ms), so what remains is the call's trip over loopback and the
#: scheduling of two processes on a loaded 2-CPU machine, a few ms. Waiting
#: for a thread, it took 0.5 s: ten times this bound, so a stop held behind
#: the blocking calls fails the test however the machine is loaded.
PROMPT = 0.06


@pytest.fixture
def clients(sim: SimProcess) -> Iterator[list[Any]]:
    """One ALMotion client per joint in JOINTS, and one more: the stopper."""
    sessions = []
    try:
        for _ in range(len(JOINTS) + 1):
            session = qi.Session()
            sessions.append(session)
            session.connect(sim.url)
        yield [session.service("ALMotion") for session in sessions]
    finally:
        for session in sessions:
            session.close()


def _log(sim: SimProcess) -> list[dict[str, Any]]:
    assert sim.log_path is not None
    return read_log(Path(sim.log_path))


def _wait_for_motions(sim: SimProcess, count: int, timeout: float = 20.0) -> None:
    """Until the sim logged ``count`` accepted motions, read from its log
    file: a call to the sim meanwhile would let libqi grow its pool first."""
    deadline = time.monotonic() + timeout
    while sum(e["event"] == "motion" for e in _log(sim)) < count:
        assert time.monotonic() < deadline, "the blocking calls were not accepted"
        time.sleep(0.01)


def test_a_stop_behind_blocking_calls_acts_at_once(
    sim: SimProcess, clients: list[Any]
) -> None:
    """Four clients each move a joint for DURATION s with angleInterpolation;
    a fifth stops both arms. The sim's log puts the interruption within
    PROMPT of the moment the stop was sent; each blocking call then fails
    as interrupted, and the joints hold where they were stopped."""
    movers, stopper = clients[:-1], clients[-1]
    starts = stopper.getAngles(JOINTS, False)  # before: no call to make after
    calls = [
        mover.angleInterpolation(joint, start + 0.2, DURATION, True, _async=True)
        for mover, joint, start in zip(movers, JOINTS, starts, strict=True)
    ]
    _wait_for_motions(sim, len(JOINTS))
    sent = time.monotonic()
    stopper.killTasksUsingResources(["LArm", "RArm"])
    log = _log(sim)
    origin = next(float(e["origin"]) for e in log if e["event"] == "start")
    interrupted = [e for e in log if e["event"] == "interrupted"]
    assert sorted(j for e in interrupted for j in e["joints"]) == sorted(JOINTS)
    late = max(origin + float(e["t"]) for e in interrupted) - sent
    assert late < PROMPT, f"the stop took effect {late:.3f} s after it was sent"
    for call in calls:
        call.wait(10000)
        assert call.hasError()
        error = call.error()
        assert error.startswith("SimCommandError: angleInterpolation was interrupted")
        assert "killTasksUsingResources" in error
    held = stopper.getAngles(JOINTS, False)
    time.sleep(0.1)
    assert stopper.getAngles(JOINTS, False) == held
    assert all(abs(h - s) < 0.2 - 1e-3 for h, s in zip(held, starts, strict=True))
