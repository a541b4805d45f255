"""A replay on the secured router says which messages its login may not publish.

`armplan replay` with the client's file printed "sent 3 of 3 messages" and
exited 0 while the router dropped every one (only a topic's publisher may
put it). Now it warns, naming the topics and whose they are, before sending;
with the planner's file the planner's keys go through, without a warning.
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import threading
import time
from collections.abc import Iterator

import pytest
import zenoh
from native_processes import Native

from armplan.launch import catalog, free_endpoint
from armplan.secure import Bundle, write_bundle
from services.recorder import RecorderProcess
from shared.bus import Bus, BusConfig, load_config, open_router

ROOT = pathlib.Path(__file__).resolve().parent.parent
#: How long a message that should not come is waited for [s].
QUIET = 2.0
MESSAGES = [
    ("plan/trajectory", b'{"replayed": 1}'),
    ("bridge/state", b'{"replayed": 2}'),
    ("plan/trajectory", b'{"replayed": 3}'),
]


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """Three messages recorded on a plain router: two trajectories, a state."""
    out = tmp_path_factory.mktemp("recording") / "session.mcap"
    config = BusConfig(endpoints=(free_endpoint(),))
    with (
        open_router(config),
        RecorderProcess.start(config, out, keys=["plan/*", "bridge/*"]),
        Bus.connect(config) as bus,
    ):
        for key, payload in MESSAGES:
            bus.session.put(bus.key(key), payload)
        time.sleep(0.5)
    return out


@pytest.fixture(scope="module")
def secured(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Bundle]:
    folder = tmp_path_factory.mktemp("secure")
    port = free_endpoint().rsplit(":", 1)[1]
    bundle = write_bundle(folder, endpoint=f"tls/127.0.0.1:{port}")
    argv = ["python", "-m", catalog.ROUTER_MODULE, "--config"]
    router = Native("router", [*argv, str(bundle.router_config)], folder / "r.log")
    try:
        yield bundle
    finally:
        router.stop()


class Inbox:
    """What the recorder's login receives on armplan/**."""

    def __init__(self, bus: Bus) -> None:
        self.payloads: list[bytes] = []
        self._lock = threading.Lock()
        self._sub = bus.session.declare_subscriber("armplan/**", self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        with self._lock:
            self.payloads.append(sample.payload.to_bytes())

    def wait(self, count: int, timeout: float) -> list[bytes]:
        deadline = time.monotonic() + timeout
        while len(self.payloads) < count and time.monotonic() < deadline:
            time.sleep(0.02)
        return list(self.payloads)


def replay(recording: pathlib.Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", "armplan", "replay", str(recording), *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        env=env,
    )


def test_a_replay_warns_of_what_its_login_may_not_publish(
    recording: pathlib.Path, secured: Bundle
) -> None:
    recorder = load_config(secured.clients["recorder"])
    with Bus.connect(recorder, wait=30) as bus:
        inbox = Inbox(bus)
        planner = secured.clients["planner"]
        done = replay(recording, "--keys", "plan/trajectory", "--config", str(planner))
        assert done.returncode == 0, done.stderr
        assert "warning" not in done.stderr
        assert inbox.wait(2, 20.0) == [MESSAGES[0][1], MESSAGES[2][1]]

        client = secured.clients["client"]
        done = replay(recording, "--config", str(client), "--wait", "30")
        assert done.returncode == 0, done.stderr
        assert done.stderr == (
            f"armplan replay: warning: {client} logs in as user 'client', which "
            "the secured router's rules do not let publish plan/trajectory (2 "
            "messages, planner's), bridge/state (1 message, bridge's): the "
            "router drops those messages without a word. Replay each "
            "publisher's keys with its own file, e.g. --keys plan/trajectory "
            "--config DIR/planner.json5, or replay into an unsecured router\n"
        )
        assert done.stdout.startswith("armplan replay: sent 3 of 3 messages")
        assert done.stdout.endswith(
            "; a secured router drops the 3 user 'client' may not publish\n"
        )
        assert len(inbox.wait(3, QUIET)) == 2  # nothing more came
