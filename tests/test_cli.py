"""The armplan command line, run as a real process."""

from __future__ import annotations

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest
from armplan_cli import armplan

from shared.robot import load_arm


def test_fk_json_contract() -> None:
    """fk --json prints shoulder, elbow, wrist, hand as [x, y, z] lists [m]."""
    out = armplan(
        "fk",
        "--arm",
        "right",
        "--joints",
        "1.2",
        "-0.3",
        "0.5",
        "0.4",
        "-1e-1",
        "--json",
    )
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert list(data) == ["shoulder", "elbow", "wrist", "hand"]
    points = load_arm("right").fk(np.array([1.2, -0.3, 0.5, 0.4, -0.1]))
    for name, value in data.items():
        np.testing.assert_allclose(value, getattr(points, name), atol=1e-12)


def test_ik_json_contract_and_negative_numbers() -> None:
    """ik --json keys joints by NAO name and reports the reached wrist."""
    out = armplan("ik", "--arm", "right", "--target", "0.12", "-0.13", "0.05", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert list(data["joints"]) == list(load_arm("right").joint_names)
    q = np.array(list(data["joints"].values()))
    wrist = load_arm("right").fk(q).wrist
    np.testing.assert_allclose(data["wrist"], wrist, atol=1e-12)
    assert np.linalg.norm(wrist - [0.12, -0.13, 0.05]) < 1e-3


@pytest.mark.parametrize("method", ["mp", "least-norm", "single"])
def test_ik_methods(method: str) -> None:
    """Every method answers the same contract."""
    out = armplan(
        "ik",
        "--arm",
        "left",
        "--target",
        "0.12",
        "0.13",
        "0.05",
        "--method",
        method,
        "--json",
    )
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["method"] == method


@pytest.mark.parametrize(
    "args,message",
    [
        (
            ("ik", "--target", "0.5", "-0.12", "0.05"),
            "from the right shoulder; the wrist reaches",
        ),
        (
            ("ik", "--target", "nan", "-0.12", "0.05"),
            "target[0] must be a finite number",
        ),
        (("ik", "--arm", "middle", "--target", "0.12", "-0.13", "0.05"), "arm"),
        (
            ("fk", "--arm", "middle", "--joints", "0", "0", "0", "0.5", "0"),
            "unknown arm 'middle'",
        ),
        (
            ("ik", "--target", "0.12", "-0.13", "0.05", "--primitive", "X_Y"),
            "unknown movement primitive",
        ),
        (
            ("ik", "--target", "0.12", "-0.13", "0.05", "--primitive", "E_R W_P"),
            "cannot reach",
        ),
        (
            ("fk", "--joints", "0", "0", "0", "3", "0"),
            "RElbowRoll = 3.00000 rad is outside",
        ),
        (
            (
                "ik",
                "--target",
                "0.12",
                "-0.1",
                "0.05",
                "--start",
                *["90", "-10", "45", "30", "0"],
            ),
            "RShoulderPitch = 90.00000 rad in the start posture is outside its range "
            "[-2.08567, 2.08567] rad; it looks like degrees: angles are in radians, "
            "and (1.5708, -0.1745, 0.7854, 0.5236, 0.0000) rad is within every "
            "joint's range",
        ),
        (
            (
                "plan",
                "--arm",
                "left",
                *["--target", "0.12", "0.13", "0.05"],
                *["--start", "1.5708", "-0.1", "1.5708", "0.2", "0"],
            ),
            "LElbowRoll = 0.20000 rad in the start posture is outside its range "
            "[-1.54462, -0.03491] rad; if it is a posture of the right arm, the "
            "left arm's mirror of it (ShoulderPitch kept, the other joints "
            "negated) is (1.5708, 0.1000, -1.5708, -0.2000, 0.0000) rad",
        ),
        (("sim", "--period", "0"), "control cycle 0.0 s must be 0.001..1 s"),
        (("sim", "--period", "nan"), "control cycle nan s must be"),
        (
            ("sim", "--listen", "tcp://127.0.0.1:99999"),
            "listen address 'tcp://127.0.0.1:99999' must look like",
        ),
        (("sim", "--listen", "garbage"), "listen address 'garbage'"),
    ],
)
def test_bad_input_gives_a_clear_error_and_no_traceback(
    args: tuple[str, ...], message: str
) -> None:
    """Each bad input exits 1 with 'armplan: error: ...' naming the problem."""
    out = armplan(*args)
    assert out.returncode == 1
    assert out.stderr.startswith("armplan: error: ")
    assert message in out.stderr
    assert "Traceback" not in out.stderr


def test_up_checks_the_robot_address_before_starting_anything() -> None:
    """up --robot garbage: the one error line, and no router or service was
    started first (they used to start, log that they were ready, and stop)."""
    from armplan.launch import free_endpoint

    out = armplan("up", "--robot", "garbage", "--listen", free_endpoint())
    assert out.returncode == 1
    assert out.stderr == (
        "armplan: error: robot address 'garbage' must look like tcp://HOST:PORT "
        "(a real NAO: tcp://IP:9559)\n"
    )


@pytest.mark.parametrize(
    "command", [("fit", "absent.mcap", "-o", "m.json"), ("faults", "--seed", "-1")]
)
def test_an_error_is_one_line_on_stderr(
    command: tuple[str, ...], tmp_path: pathlib.Path
) -> None:
    """fit's progress display left a blank line before its error; faults took a
    negative seed. Each error is now the one line on stderr, nothing else."""
    out = subprocess.run(
        [sys.executable, "-m", "armplan", *command],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        check=False,
    )
    assert out.returncode == 1
    assert out.stderr.startswith("armplan: error: ")
    assert out.stderr.count("\n") == 1 and out.stderr.endswith("\n")


def test_json_errors_are_machine_readable() -> None:
    """With --json an error is also printed as {"error": {kind, message, evidence}}."""
    out = armplan("ik", "--target", "0.5", "-0.12", "0.05", "--json")
    assert out.returncode == 1
    error = json.loads(out.stdout)["error"]
    assert error["kind"] == "unreachable_target"
    assert error["evidence"]["target"] == [0.5, -0.12, 0.05]


def test_malformed_command_line_is_a_usage_error() -> None:
    """Missing or non-numeric values exit 2 with argparse's usage message."""
    out = armplan("ik", "--target", "0.1", "abc", "0.0")
    assert out.returncode == 2 and "invalid float value: 'abc'" in out.stderr


def test_readable_output_without_json() -> None:
    """Without --json, ik prints a table and the reached wrist."""
    out = armplan("ik", "--target", "0.12", "-0.13", "0.05")
    assert out.returncode == 0
    assert "RShoulderPitch" in out.stdout and "mm from the target" in out.stdout


def test_json_output_is_strict(capsys: pytest.CaptureFixture[str]) -> None:
    """NaN and infinities, which strict JSON readers refuse, print as null."""
    from armplan.cli.output import print_json

    print_json({"gap": float("nan"), "rows": [1.5, float("inf")], "pair": (2, None)})
    assert json.loads(capsys.readouterr().out) == {
        "gap": None,
        "rows": [1.5, None],
        "pair": [2, None],
    }


@pytest.mark.parametrize(("side", "y"), [("right", "-0.08"), ("left", "0.08")])
def test_ik_table_round_trips_within_the_limits(side: str, y: str) -> None:
    """The angles ik prints (here ShoulderRoll on its limit) are accepted back
    by fk --joints and ik --start, and fk puts the wrist on the target."""
    out = armplan("ik", "--arm", side, "--target", "0.1", y, "0.0")
    assert out.returncode == 0, out.stderr
    printed = [line.split()[1] for line in out.stdout.splitlines()[1:6]]
    q = np.array([float(v) for v in printed])
    fk = armplan("fk", "--arm", side, "--joints", *printed, "--json")
    assert fk.returncode == 0, fk.stderr
    assert (
        np.linalg.norm(np.array(json.loads(fk.stdout)["wrist"]) - [0.1, float(y), 0])
        < 1e-4
    )
    again = armplan(
        "ik", "--arm", side, "--target", "0.1", y, "0.0", "--start", *printed
    )
    assert again.returncode == 0, again.stderr
    limits = load_arm(side).limits
    assert np.any((q == limits.lower) | (q == limits.upper))  # a limit was printed


def test_angle_text_stays_within_the_range(rng: np.random.Generator) -> None:
    """Each printed angle is the true one rounded (to 5 decimals where that
    stays in range) and reads back within the joint's range, limits included."""
    from armplan.cli.output import angle_text

    for side in ("right", "left"):
        limits = load_arm(side).limits
        inside = rng.uniform(limits.lower, limits.upper, size=(200, 5))
        for q in [limits.lower, limits.upper, *inside]:
            for value, low, high in zip(q, limits.lower, limits.upper, strict=True):
                text = angle_text(float(value), low, high)
                digits = len(text.split(".")[1])
                assert low <= float(text) <= high
                assert abs(float(text) - value) <= 0.5 * 10.0**-digits
                assert digits == 5 or not low <= round(value, 5) <= high
