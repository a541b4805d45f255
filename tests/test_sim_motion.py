"""The simulated NAO's ALMotion, in this process on a clock of its own.

A long ``angleInterpolation`` takes the sim time to read and to log (44 000
keys: 0.1 s to read, 0.3 s to write in the log) while its control cycle
goes on. The keys must count from when the command takes effect: counted
from its arrival, they ran on while the joints held the last command, and
the joints then caught up at their speed limit, an error a NAO never makes.
Here the clock moves on, and the cycle steps, exactly when the sim reads
the keys or writes the call's line.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from bridge.qi_future import wait_future
from bridge.sim import motion as sim_motion
from bridge.sim.log import KEEP, SimLog
from bridge.sim.motion import SimulatedMotion
from bridge.sim.robot import SimRobot
from bridge.sim.task import MotionTask

#: Time the sim spends on the call, reading its keys or writing its line [s].
TAKES = 0.3
#: The ramp's mean speed [rad/s]: one key, SPEED away, 1 s on.
SPEED = 0.5


def _on_ramp(s: float) -> float:
    """Where the ramp is ``s`` seconds after it took effect [rad]: one key,
    so its curve is the cubic at rest at both ends."""
    return -SPEED * (3.0 * s**2 - 2.0 * s**3)


class _Sim:
    """A simulated NAO on a clock that moves only when told to."""

    def __init__(self) -> None:
        self.log = _SlowToWrite(self)
        self.now = self.log.origin + 1.0
        self.robot = SimRobot(self.log, {"RShoulderPitch": 0.0}, clock=self.clock)
        self.robot.stiffen("setStiffnesses", self.now, "RShoulderPitch", [1.0], [1e-3])
        self.motion = SimulatedMotion(self.robot, self.log)
        self.slow_to_write = False

    def clock(self) -> float:
        return self.now

    def spend(self, duration: float) -> None:
        """``duration`` [s] passes, and the control cycle steps."""
        self.now += duration
        self.robot.step()

    def measured(self) -> float:
        return self.robot.angles("RShoulderPitch", True)[0]


class _SlowToWrite(SimLog):
    """A log whose ``call`` lines take ``TAKES`` to write when asked to."""

    def __init__(self, sim: _Sim) -> None:
        super().__init__(keep=KEEP)
        self.sim = sim
        self.applied = threading.Event()

    def write(self, event: str, at: float | None = None, **fields: Any) -> None:
        if event == "call" and self.sim.slow_to_write:
            self.sim.spend(TAKES)
        super().write(event, at, **fields)
        if event == "motion":
            self.applied.set()


class _SlowToRead(list[float]):
    """Keys that take ``TAKES`` to read, the first time they are read."""

    def __init__(self, keys: list[float], spend: Callable[[float], None]) -> None:
        super().__init__(keys)
        self.spend: Callable[[float], None] | None = spend

    def __iter__(self) -> Iterator[float]:
        if self.spend is not None:
            spend, self.spend = self.spend, None
            spend(TAKES)
        return super().__iter__()


def _ramp(sim: _Sim, keys: list[float]) -> tuple[float, Any]:
    """Send a ramp at ``SPEED`` over 1 s; once it took effect: the clock
    when it was sent [s], and the call's answer (a ``qi.Future``), which
    blocks its caller until the ramp ends."""
    sent = sim.now
    answer = sim.motion.angleInterpolation("RShoulderPitch", keys, [1.0], True)
    assert sim.log.applied.is_set()
    assert not answer.isFinished()
    return sent, answer


def _finish(sim: _Sim, answer: Any) -> None:
    sim.spend(1.0)  # past the ramp's end: the blocking call is answered
    assert answer.isFinished() and answer.hasValue() and answer.value() is None


@pytest.fixture
def sim() -> _Sim:
    made = _Sim()
    made.spend(0.01)  # stiff
    return made


def test_the_joints_take_a_call_before_its_log_line_is_written(sim: _Sim) -> None:
    """Written meanwhile, TAKES after the ramp took effect the joint is on it
    (it used to hold still until the line was written, then catch up); the
    line says when the keys count from."""
    sim.slow_to_write = True
    sent, answer = _ramp(sim, [-SPEED])
    try:
        assert sim.now == pytest.approx(sent + TAKES)
        assert sim.measured() == pytest.approx(_on_ramp(TAKES), abs=1e-9)
    finally:
        _finish(sim, answer)
    entry = next(e for e in sim.log.entries() if e["event"] == "call")
    assert entry["t"] == pytest.approx(sent - sim.log.origin, abs=1e-6)
    assert entry["method"] == "angleInterpolation" and entry["angles"] == [-SPEED]


def test_the_keys_count_from_when_they_were_read(sim: _Sim) -> None:
    """Keys that take TAKES to read: the ramp starts once read, at its own
    speed (it used to start at the call's arrival, so the joint, held
    meanwhile, then ran at 4 times the ramp's speed to catch up)."""
    sent, answer = _ramp(sim, _SlowToRead([-SPEED], sim.spend))
    try:
        assert sim.now == pytest.approx(sent + TAKES)
        assert sim.measured() == 0.0
        sim.spend(0.1)
        assert sim.measured() == pytest.approx(_on_ramp(0.1), abs=1e-9)
    finally:
        _finish(sim, answer)
    entry = next(e for e in sim.log.entries() if e["event"] == "call")
    assert entry["t"] == pytest.approx(sent + TAKES - sim.log.origin, abs=1e-6)
    done = next(
        e
        for e in sim.log.entries()
        if e["event"] == "done" and e["method"] == "angleInterpolation"
    )
    assert done["t"] >= entry["t"] + 1.0


def test_a_task_is_answered_once_by_its_first_end() -> None:
    """Interrupted as the cycle finishes it (a new command took its joint
    between the cycle's look and its finish), then overdue: one answer, the
    interruption's. Answered on asking if it already ended; a task made
    with killed_returns answers an interruption as a normal return."""
    answers: list[str | None] = []
    task = MotionTask("angleInterpolation", ["RShoulderPitch"], 0.0, 1.0)
    task.answer(answers.append)
    task.interrupt("killAll")
    task.finish()
    task.expire()
    assert answers == ["angleInterpolation was interrupted: killAll"]
    assert task.finished
    ended = MotionTask("angleInterpolation", ["RShoulderPitch"], 0.0, 1.0)
    ended.finish()
    ended.answer(answers.append)
    killed = MotionTask("angleInterpolation", ["RShoulderPitch"], 0.0, 1.0, True)
    killed.answer(answers.append)
    killed.interrupt("killAll")
    assert answers[1:] == [None, None]


def test_a_call_whose_task_never_ends_fails_past_its_grace(
    sim: _Sim, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The clock stands still, so the cycle never finishes the 0.1 s ramp: a
    libqi timer fails its call GRACE past its duration (no thread waits for
    it); the joints' task goes on, still booking them, as it did."""
    monkeypatch.setattr(sim_motion, "GRACE", 0.1)
    answer = sim.motion.angleInterpolation("RShoulderPitch", [-0.01], [0.1], True)
    assert wait_future(answer, 10.0)
    assert answer.hasError()
    error = answer.error()
    assert error == "SimCommandError: angleInterpolation did not finish in time"
    assert not sim.motion.areResourcesAvailable("RShoulderPitch")
    sim.spend(0.2)
    assert sim.motion.areResourcesAvailable("RShoulderPitch")
