"""`armplan ik` and `armplan plan` say how near the palm came (cli/palm_line.py)."""

from __future__ import annotations

import json
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

from armplan.cli.main import main
from shared.messages import IKResult, Trajectory, parse
from shared.robot import load_arm
from shared.robot.arm_model import ArmModel

TARGET = ("0.12", "-0.13", "0.05")
OTHER = ("0.10", "-0.14", "0.0")
UP = np.array([0.0, 0.0, 1.0])
#: The line both commands print, its angle [deg] and normal captured.
LINE = (
    r"palm{where} ([\d.]+) deg from the wanted direction \(0\.000, 0\.000, 1\.000\): "
    r"normal \((\S+), (\S+), (\S+)\) \(only its roll about the forearm is controlled\)"
)


def armplan(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def fk_angle(arm: ArmModel, q: list[float] | np.ndarray) -> float:
    """The right palm's angle from straight up [deg], by pinocchio's kinematics."""
    normal = arm.side.sign * arm.rotation(np.asarray(q), "wrist")[:, 1]
    return float(np.degrees(np.arccos(np.clip(normal @ UP, -1.0, 1.0))))


def test_ik_prints_and_its_json_carries_the_palm_reached() -> None:
    """ik --palm 0 0 1 at the hunter's target: the palm 25.7 deg off, printed
    and in the JSON, as forward kinematics of the joints printed finds."""
    arm = load_arm("right")
    out = armplan("ik", "--target", *TARGET, "--palm", "0", "0", "1")
    assert out.returncode == 0, out.stderr
    line = re.search(LINE.format(where=""), out.stdout)
    assert line is not None, out.stdout
    assert float(line[1]) == pytest.approx(25.7, abs=0.05)
    out = armplan("ik", "--target", *TARGET, "--palm", "0", "0", "1", "--json")
    assert out.returncode == 0, out.stderr
    result = parse(IKResult, out.stdout)
    assert result.palm_reached is not None
    angle = fk_angle(arm, list(result.joints.values()))
    assert result.palm_reached.angle_deg == pytest.approx(angle, abs=1e-6)
    assert f"{angle:.1f}" == line[1]


def test_ik_without_a_palm_says_nothing_of_it() -> None:
    """Without --palm neither the text nor the JSON speaks of a palm."""
    out = armplan("ik", "--target", *TARGET, "--json")
    assert out.returncode == 0, out.stderr
    assert "palm_reached" not in json.loads(out.stdout)
    assert "palm" not in armplan("ik", "--target", *TARGET).stdout


def test_plan_json_carries_the_palm_at_each_target(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """plan --json: one palm_reached entry per target, null where none was
    asked; the last is the palm of the trajectory's last sample."""
    arm = load_arm("right")
    args = ["plan", "--target", *OTHER, "--target", *TARGET, "--palm", "0", "0", "1"]
    assert main([*args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    first, last = data["palm_reached"]
    assert first is None
    assert last["wanted"] == [0.0, 0.0, 1.0]
    angle = fk_angle(arm, data["positions"][-1])
    assert last["angle_deg"] == pytest.approx(angle, abs=1e-6)
    assert angle > 10.0  # the roll is met, the direction is not
    assert parse(Trajectory, data).palm_reached is not None


def test_plan_summary_says_the_palm_reached(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """plan --palm's summary prints the palm's angle beside the wrist error,
    as forward kinematics of the last sample finds it (22.8 deg here)."""
    assert main(["plan", "--target", *TARGET, "--palm", "0", "0", "1", "--json"]) == 0
    trajectory = parse(Trajectory, capsys.readouterr().out)
    assert main(["plan", "--target", *TARGET, "--palm", "0", "0", "1"]) == 0
    summary = capsys.readouterr().out.split("\n\n")[1]
    assert "final wrist error 0.000 mm" in summary
    line = re.search(LINE.format(where=" at the target"), summary)
    assert line is not None, summary
    angle = fk_angle(load_arm("right"), trajectory.positions[-1])
    assert line[1] == f"{angle:.1f}" == "22.8"


def test_a_wrist_paths_palm_is_reported_at_its_last_sample(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """plan --wrist-path --palm: one entry, the palm of the last sample."""
    arm = load_arm("right")
    start = arm.fk(np.array([0.6, -0.4, 0.5, 1.1, 0.9])).wrist
    rows = ["t,x,y,z"] + [
        f"{k * 0.01:.2f},{start[0]:.9f},{start[1]:.9f},{start[2]:.9f}"
        for k in range(20)
    ]
    file = tmp_path / "still.csv"
    file.write_text("\n".join(rows) + "\n")
    args = ["plan", "--wrist-path", str(file), "--palm", "0", "0", "1"]
    assert main([*args, "--json"]) == 0
    trajectory = parse(Trajectory, capsys.readouterr().out)
    assert trajectory.palm_reached is not None
    (reached,) = trajectory.palm_reached
    assert reached is not None
    angle = fk_angle(arm, trajectory.positions[-1])
    assert reached.angle_deg == pytest.approx(angle, abs=1e-6)
    assert main(args) == 0
    summary = capsys.readouterr().out
    assert re.search(LINE.format(where=" at the path's last sample"), summary)
