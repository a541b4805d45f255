"""``ik`` and ``decide`` refuse a second ``--target`` rather than drop the first."""

from __future__ import annotations

import pytest
from armplan_cli import armplan

FAR, NEAR = ("9", "9", "9"), ("0.12", "-0.13", "0.05")


@pytest.mark.parametrize("command", ["ik", "decide"])
def test_a_second_target_is_a_malformed_command_line(command: str) -> None:
    """``--target A --target B`` answered for B alone, exit 0, A dropped."""
    out = armplan(command, "--target", *FAR, "--target", *NEAR)
    assert out.returncode == 2, out.stdout
    assert out.stdout == ""
    assert (
        f"armplan {command}: error: argument --target: given twice: {command} "
        "takes one target (armplan plan reaches several, one after another)"
    ) in out.stderr
    assert "Traceback" not in out.stderr


def test_one_target_is_answered() -> None:
    """One ``--target`` is solved as before."""
    out = armplan("ik", "--target", *NEAR)
    assert out.returncode == 0, out.stderr
    assert "wrist (0.1200, -0.1300, 0.0500) m, 0.000 mm from the target" in out.stdout
