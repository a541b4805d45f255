"""Which robot ``python -m bridge`` (the bridge on stdin/stdout) drives.

``--robot``, else ``$ARMPLAN_ROBOT``, else the simulated NAO's address, as
``python -m bridge.serve``; an address that is not ``tcp://HOST:PORT`` ends
it at start (exit 1), before a line is read. It used to ignore
``$ARMPLAN_ROBOT``, take ``127.0.0.1:47800``, answer every request to
``tcp://127.0.0.1:99999`` with robot_unavailable and fail on ``http://``
only at the first request. Real processes: the bridge, and the simulated
NAO over libqi.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from shared.messages import ExecuteReply, ExecuteRequest
from shared.robot.postures import rest


def _run(
    *args: str, env: dict[str, str], lines: str = ""
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "bridge", *args],
        input=lines,
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, **env},
    )


@pytest.mark.parametrize(
    ("args", "env", "bad"),
    [
        (("--robot", "127.0.0.1:47800"), {}, "127.0.0.1:47800"),
        (("--robot", "tcp://127.0.0.1:99999"), {}, "tcp://127.0.0.1:99999"),
        (("--robot", "http://127.0.0.1:9559"), {}, "http://127.0.0.1:9559"),
        ((), {"ARMPLAN_ROBOT": "garbage"}, "garbage"),
    ],
)
def test_an_address_not_tcp_host_port_ends_the_bridge_at_start(
    args: tuple[str, ...], env: dict[str, str], bad: str
) -> None:
    """Exit 1, one line naming the address and its form; no reply."""
    request = ExecuteRequest(
        trajectory=minimum_jerk_trajectory("right", [rest("right")] * 2, [0.5])
    )
    done = _run(*args, env=env, lines=request.to_json() + "\n")
    assert done.returncode == 1, done.stderr
    assert done.stdout == ""
    assert done.stderr == (
        f"python -m bridge: error: robot address {bad!r} must look like "
        "tcp://HOST:PORT (a real NAO: tcp://IP:9559)\n"
    )


def test_the_robot_is_the_option_else_the_environments(sim: SimProcess) -> None:
    """$ARMPLAN_ROBOT names the sim: played there. --robot names it while
    $ARMPLAN_ROBOT is garbage: the option wins, played there too."""
    hold = minimum_jerk_trajectory("right", [rest("right")] * 2, [0.5])
    line = ExecuteRequest(trajectory=hold).to_json() + "\n"
    for args, env in (
        ((), {"ARMPLAN_ROBOT": sim.url}),
        (("--robot", sim.url), {"ARMPLAN_ROBOT": "garbage"}),
    ):
        done = _run(*args, env=env, lines=line)
        assert done.returncode == 0, done.stderr
        reply = ExecuteReply.model_validate(json.loads(done.stdout))
        assert reply.frames > 0
