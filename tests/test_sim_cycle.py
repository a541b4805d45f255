"""The simulated NAO's control cycle: its schedule and the times its log gives."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.sim.cycle import ControlCycle, check_period, next_slot
from bridge.sim.joints import joint_specs
from bridge.sim.log import KEEP, SimLog
from bridge.sim.robot import SimRobot
from shared.errors import InvalidInputError


@pytest.mark.parametrize("late", [0.0, 0.003, 0.0199, 0.02, 0.031, 0.095])
def test_next_slot_is_the_first_slot_of_the_schedule_after_now(late: float) -> None:
    last, period = 10.0, 0.02
    now = last + late
    slot = next_slot(last, period, now)
    k = (slot - last) / period
    assert k == pytest.approx(round(k)) and round(k) >= 1  # on the schedule
    assert now < slot <= now + period + 1e-12  # the first one after now


def test_state_lines_carry_the_time_the_positions_were_committed() -> None:
    """The cycle's clock, not the moment the line is written, stamps a state:
    with a clock that jumps (a late cycle), the logged speed stays the motor's."""
    log = SimLog(keep=KEEP)
    now = [log.origin + 1.0]
    robot = SimRobot(log, {"RShoulderPitch": 1.0}, clock=lambda: now[0])
    robot.stiffen("setStiffnesses", now[0], "RShoulderPitch", [1.0], [0.001])
    now[0] += 0.01
    robot.move("angleInterpolation", now[0], "RShoulderPitch", [0.0], [0.5])
    steps = [0.02, 0.02, 0.039, 0.0013, 0.02, 0.02]  # a late cycle, then a quick one
    for dt in steps:
        now[0] += dt
        robot.step()
    states = [e for e in log.entries() if e["event"] == "state"]
    stamps = np.array([e["t"] for e in states])
    angles = np.array([e["positions"]["RShoulderPitch"] for e in states])
    assert stamps == pytest.approx(1.01 + np.cumsum(steps))
    speed = np.abs(np.diff(angles)) / np.diff(stamps)
    limit = joint_specs()["RShoulderPitch"].velocity
    assert speed.max() <= limit * 1.001
    assert angles[-1] < 1.0  # it moved


@pytest.mark.parametrize("period", [0.0, 0.0005, 1.5, 1e308, float("nan"), -0.02])
def test_a_control_cycle_out_of_range_is_refused(period: float) -> None:
    """0 once divided by zero in the cycle's thread, 1e308 overflowed its
    clock and NaN its slot count, each leaving a sim that no longer moved:
    the cycle is refused before any thread starts; 0.001..1 s is accepted."""
    with pytest.raises(InvalidInputError, match="control cycle"):
        check_period(period)
    with pytest.raises(InvalidInputError):
        ControlCycle(SimRobot(SimLog(None), {"RShoulderPitch": 1.0}), period)
    assert check_period(0.001) == 0.001 and check_period(1.0) == 1.0


@pytest.mark.parametrize(("sag", "fell"), [(0.3, 0.3), (0.0, 0.0)])
def test_a_joint_let_go_with_a_sag_falls_toward_rest_for_that_long(
    sag: float, fell: float
) -> None:
    """With a sag of 0.3 s a joint let go falls toward its starting angle at
    1 rad/s for 0.3 s (readings between cycles too), then holds. Without a
    sag it holds at once."""
    log = SimLog()
    now = [log.origin + 1.0]
    robot = SimRobot(log, {"RShoulderPitch": 1.0}, clock=lambda: now[0], sag=sag)
    robot.stiffen("setStiffnesses", now[0], "RShoulderPitch", [1.0], [0.001])
    now[0] += 0.01
    robot.move("angleInterpolation", now[0], "RShoulderPitch", [0.0], [0.2])
    for _ in range(20):
        now[0] += 0.02
        robot.step()
    assert robot.angles("RShoulderPitch", True)[0] == pytest.approx(0.0)
    robot.stiffen("setStiffnesses", now[0], "RShoulderPitch", [0.0], [0.001])
    now[0] += 0.001
    robot.step()
    readings = []
    for _ in range(30):
        now[0] += 0.01  # a reading between cycles, then a cycle
        readings.append(robot.angles("RShoulderPitch", True)[0])
        now[0] += 0.01
        robot.step()
    assert readings[-1] == pytest.approx(fell, abs=1e-6)
    if sag:
        assert 0.109 < readings[5] < 0.112  # mid-fall, 0.11 s after let go


@pytest.mark.parametrize("sag", [-0.1, float("nan"), 11.0])
def test_a_sag_out_of_range_is_refused(sag: float) -> None:
    from shared.sim_options import check_sag

    with pytest.raises(InvalidInputError, match=r"--limp-sag must be 0\.\.10 s"):
        check_sag(sag)
    check_sag(0.0)
    check_sag(0.3)


def test_a_hand_holding_an_object_closes_no_further() -> None:
    """With ``grip`` 0.3 a hand commanded shut stops at 0.3 (the object's
    width), read between cycles too; commanded open, it opens past it."""
    log = SimLog()
    now = [log.origin + 1.0]
    robot = SimRobot(log, {"RHand": 1.0}, clock=lambda: now[0], grip=0.3)
    robot.stiffen("setStiffnesses", now[0], "RHand", [1.0], [0.001])
    now[0] += 0.01
    robot.move("angleInterpolation", now[0], "RHand", [0.0], [0.5])
    for _ in range(40):
        now[0] += 0.02
        robot.step()
    now[0] += 0.01
    assert robot.angles("RHand", True)[0] == pytest.approx(0.3)
    assert robot.angles("RHand", False)[0] == pytest.approx(0.0)
    robot.move("angleInterpolation", now[0], "RHand", [0.8], [0.5])
    for _ in range(40):
        now[0] += 0.02
        robot.step()
    assert robot.angles("RHand", True)[0] == pytest.approx(0.8)
    assert robot.angles("RShoulderPitch", True)[0] == pytest.approx(0.0)  # no stop


@pytest.mark.parametrize("grip", [-0.1, float("nan"), 1.5])
def test_a_grip_out_of_range_is_refused(grip: float) -> None:
    from shared.sim_options import check_grip

    with pytest.raises(InvalidInputError, match=r"--grip must be an open fraction"):
        check_grip(grip)
    check_grip(None)
    check_grip(0.3)
