"""A replay whose router goes away says how many messages reached nobody.

A put gets no answer, and Zenoh reconnects a client by itself: a replay
whose router was killed after 4 of its 10.6 s (restarted 6 s later, or not
at all) said "sent 175 of 175 messages" and exited 0, while a recorder
beside it kept 75. Here a real router process is killed with SIGKILL while
`armplan replay` (a real process) sends a recording of ``COUNT`` messages,
``GAP`` apart; a subscriber in this test sees what arrives. A replay into a
peer (a peer-mode session listening on the endpoint, which SPEC allows) is
connected too: it counted every message as sent with no router and exited 1.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import zenoh
from native_processes import ROOT, Native

from armplan.launch import free_endpoint
from services.recorder.options import RecorderOptions
from services.recorder.routing import Incoming
from services.recorder.sink import RecordingSink
from shared.bus import Bus, BusConfig

NAMESPACE = "lostrouter"
#: Messages in the recording, and the time between two [s].
COUNT, GAP = 60, 0.1
#: Time from the first message's arrival to the kill [s].
BEFORE_KILL = 0.8


def recording(path: Path) -> Path:
    """``COUNT`` messages ``{"i": i}`` on ``misc/x``, ``GAP`` apart."""
    sink = RecordingSink(RecorderOptions(output=path, keys=("**",)), NAMESPACE)
    sink.start()
    start = time.time_ns()
    for i in range(COUNT):
        t = start + int(i * GAP * 1e9)
        sink.put(Incoming(f"{NAMESPACE}/misc/x", b'{"i": %d}' % i, "zenoh/bytes", t, t))
    sink.stop()
    return path


def start_router(endpoint: str, log: Path) -> Native:
    argv = ["python", "-m", "shared.bus.router", "--listen", endpoint]
    return Native("router", argv, log, env={"PYTHONPATH": str(ROOT)})


class Arrivals:
    """The ``i`` of each message that reaches this test's subscriber."""

    def __init__(self, bus: Bus) -> None:
        self.got: list[int] = []
        self.first = threading.Event()
        self._sub = bus.session.declare_subscriber(f"{NAMESPACE}/**", self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        self.got.append(int(sample.payload.to_bytes()[6:-1]))
        self.first.set()


@pytest.mark.parametrize("back_after", [None, 0.0], ids=["gone", "restarted"])
def test_messages_sent_with_no_router_are_counted_and_fail_the_replay(
    tmp_path: Path, back_after: float | None
) -> None:
    """SIGKILL the router 0.8 s into a 6 s replay (restarted at once, or
    not): exit 1; the summary and the error count the messages sent while
    no router or peer was connected, none of which arrived; a warning says when the
    router went and, if restarted, that it is back."""
    endpoint = free_endpoint()
    config = BusConfig(endpoints=(endpoint,), namespace=NAMESPACE)
    router = start_router(endpoint, tmp_path / "router.log")
    replay: subprocess.Popen[str] | None = None
    try:
        with Bus.connect(config, wait=30) as bus:
            arrivals = Arrivals(bus)
            command = [sys.executable, "-m", "armplan", "replay"]
            command += [str(recording(tmp_path / "s.mcap")), "--connect", endpoint]
            command += ["--namespace", NAMESPACE, "--wait", "30"]
            replay = subprocess.Popen(
                command,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env={**os.environ, "PYTHONPATH": str(ROOT)},
            )
            assert arrivals.first.wait(60), "no replayed message arrived"
            time.sleep(BEFORE_KILL)
            router.kill(signal.SIGKILL)
            router.process.wait(10)
            if back_after is not None:
                time.sleep(back_after)
                router = start_router(endpoint, tmp_path / "router2.log")
            out, err = replay.communicate(timeout=120)
            got = list(arrivals.got)
    finally:
        if replay is not None and replay.poll() is None:
            replay.kill()
            replay.wait(10)
        router.stop()
    print(out, err, f"arrived: {len(got)}", sep="\n")
    assert replay.returncode == 1, err
    found = re.search(rf"; (\d+) of {COUNT} messages went out while no router or", out)
    assert found is not None, out
    offline = int(found[1])
    assert out.startswith(f"armplan replay: sent {COUNT} of {COUNT} messages")
    assert f"{offline} of {COUNT} messages went out while no router or peer" in err
    assert f"the replay lost its connection to the router or peer at {endpoint}" in err
    assert f"warning: lost the router or peer at {endpoint}" in err
    assert "at the start" not in err
    assert len(got) + offline <= COUNT  # none sent with no router arrived
    if back_after is None:
        assert offline >= COUNT - len(got) - 2  # at most the kill's own instant
        assert f"peer at {endpoint} is back" not in err
    else:
        assert offline > 0
        assert f"the router or peer at {endpoint} is back" in err
        assert got[-1] == COUNT - 1  # the last ones went out through it again


def test_a_replay_into_a_peer_is_connected(tmp_path: Path) -> None:
    """`armplan replay --connect` to a peer-mode session listening there:
    every message arrives, exit 0, and no word of a lost or absent router
    (routers_zid lists routers only; the peer is in peers_zid)."""
    endpoint = free_endpoint()
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("listen/endpoints", json.dumps([endpoint]))
    config.insert_json5("scouting/multicast/enabled", "false")
    config.insert_json5("scouting/gossip/enabled", "false")
    got: list[str] = []
    with zenoh.open(config) as peer:
        peer.declare_subscriber(
            f"{NAMESPACE}/**", lambda sample: got.append(str(sample.key_expr))
        )
        command = [sys.executable, "-m", "armplan", "replay"]
        command += [str(recording(tmp_path / "s.mcap")), "--connect", endpoint]
        command += ["--namespace", NAMESPACE, "--wait", "30", "--speed", "10"]
        done = subprocess.run(
            command,
            capture_output=True,
            text=True,
            timeout=120,
            env={**os.environ, "PYTHONPATH": str(ROOT)},
            check=False,
        )
        deadline = time.monotonic() + 10
        while len(got) < COUNT and time.monotonic() < deadline:
            time.sleep(0.05)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"armplan replay: sent {COUNT} of {COUNT} messages")
    assert "went out while" not in done.stdout
    assert done.stderr == ""
    assert got == [f"{NAMESPACE}/misc/x"] * COUNT
