"""Two bridges started at the same moment: one runs, the other gives way.

Both used to pass the start check (neither's service token was declared
yet) and then both played every request on the robot. Real parts: a Zenoh
router (``armplan.launch``), two ``python -m bridge.serve`` processes, the
simulated NAO over libqi, and a Zenoh client session in the test.
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from armplan.launch import Launcher, free_endpoint
from bridge.claim import claim_key, claims
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.bus import Bus, BusConfig, load_config
from shared.bus.robot_routes import EXECUTE
from shared.messages import ExecuteRequest
from shared.robot.postures import forward, rest

#: Longest wait for a bridge to start or give way [s].
START = 30.0


@pytest.fixture
def config(tmp_path: Path) -> Iterator[BusConfig]:
    """A router's configuration, the router running."""
    config = load_config(endpoints=(free_endpoint(),))
    with (tmp_path / "router.log").open("w") as log, Launcher(config, [], log=log):
        yield config


def _bridge(config: BusConfig, sim: SimProcess) -> subprocess.Popen[str]:
    command = [sys.executable, "-m", "bridge.serve", "--robot", sim.url]
    command += ["--connect", config.endpoints[0]]
    return subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )


def _first_exit(bridges: list[subprocess.Popen[str]]) -> subprocess.Popen[str] | None:
    deadline = time.monotonic() + START
    while time.monotonic() < deadline:
        for bridge in bridges:
            if bridge.poll() is not None:
                return bridge
        time.sleep(0.05)
    return None


def test_of_two_bridges_started_at_once_only_one_plays(
    config: BusConfig, sim: SimProcess
) -> None:
    """Two bridges started together: one exits 1 with service_running, the
    other serves, and a request moves the arm once."""
    bridges = [_bridge(config, sim), _bridge(config, sim)]
    try:
        gave_way = _first_exit(bridges)
        assert gave_way is not None, "both bridges ran"
        _, stderr = gave_way.communicate(timeout=10.0)
        runs = next(b for b in bridges if b is not gave_way)
        with Bus.connect(config) as client:
            assert client.wait_alive(["bridge"], START) == []
            held = claims(client)
            reach = minimum_jerk_trajectory(
                "right", [rest("right"), forward("right")], [0.5]
            )
            reply = client.call(EXECUTE, ExecuteRequest(trajectory=reach), timeout=30.0)
        assert gave_way.returncode == 1, stderr
        assert "service 'bridge' is already running" in stderr
        assert runs.poll() is None
        assert len(held) == 1
        assert reply.frames > 0
        assert sim.log_path is not None
        motions = [e for e in read_log(sim.log_path) if e["event"] == "motion"]
        approach = 1 if reply.approach_duration > 0.0 else 0  # the sim starts at rest
        assert len(motions) == approach + 1  # played once, not once per bridge
    finally:
        for bridge in bridges:
            bridge.terminate()
        for bridge in bridges:
            bridge.communicate(timeout=60.0)


def test_claims_sort_by_start_time_then_session() -> None:
    """The earlier start wins whatever the ids; at one start, the smaller id."""
    early = claim_key("armplan", 999_999_999, "ff")
    late = claim_key("armplan", 1_000_000_000, "00")
    assert early < late
    assert claim_key("armplan", 5, "0a") < claim_key("armplan", 5, "0b")
    assert early.startswith("armplan/bridge/claim/")
