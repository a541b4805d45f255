"""The exported play.py's move to the start, measured on the simulated NAO.

It used ``angleInterpolationWithSpeed(names, start, 0.2)``: a straight line
at a constant speed, stepping from rest to 20 % of the speed limit at once.
From rest to ``forward`` at a 5 ms cycle the logged RShoulderPitch reached
259 rad/s^2 (3.1 times the bridge's safety net) and 31 times its jerk; at
20 ms still 1.6 times the jerk. Now it plays minimum-jerk keys
(``bridge.script_approach``) within 20 % of the limits.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
from logged_motion import logged_peaks

from bridge.frames import frames_from_trajectory
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.python_export import write_python
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.robot.postures import forward, rest


def test_play_py_reaches_the_start_within_the_nets_limits(tmp_path: Path) -> None:
    """From the sim's rest to ``forward`` at a 5 ms cycle: every joint's
    logged speed, acceleration and jerk stay within a quarter of the net."""
    there = np.array(forward("right"))
    frames = frames_from_trajectory(
        minimum_jerk_trajectory("right", [there, there], [0.5])
    )
    script = write_python(frames, tmp_path / "play.py")
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log, period=0.005) as sim:
        run = subprocess.run(
            [sys.executable, str(script), sim.url],
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
    assert run.returncode == 0, run.stdout + run.stderr
    entries = read_log(log)
    moves = [e for e in entries if e["event"] == "call" and "angles" in e]
    assert len(moves) == 2  # the approach, then the trajectory
    names = list(frames.joint_names)
    assert np.abs(np.subtract(rest("right"), there)).max() > 0.9  # a long move
    peaks = logged_peaks(entries, names, moves[0]["t"], moves[1]["t"] - 1e-6)
    net = FrameLimits.for_arm("right")
    share = peaks / np.array([net.velocity, net.acceleration, net.jerk])
    print("\nshare of the net (speed, acceleration, jerk):\n", share.round(3))
    assert share[0].max() > 0.15  # it moved, at about its 20 %
    assert share.max() < 0.25
