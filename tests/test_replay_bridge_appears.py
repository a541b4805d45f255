"""A replay of every key stops when a bridge (or a decide service) comes alive.

The refusal of an unkeyed replay into a live bridge was checked once,
before the first message: a bridge started during a long replay received
the rest of the recorded trajectories (and, with ``--follow``, played them
on the arm). Here ``armplan replay`` (a real process) sends a recording of
``COUNT`` trajectories ``GAP`` apart through a real router; once some have
arrived, a second session declares the bridge's token as a bridge does
(``ServiceHost``), and an observer session counts the trajectories that
arrive after it sees the token.

The bound: the observer and the replay each get the token from the router,
one hop away. The replay checks its flag immediately before each put, so
after it sees the token nothing more passes; what can still arrive after
the observer saw it is the put that had passed the check when the token
came (in flight): at most one, as long as the replay sees the token less
than ``GAP`` (100 ms) after the observer does (well under 1 ms on loopback;
100 ms of slack for two busy CPUs). The old code sent all ``COUNT``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from native_processes import ROOT

from armplan.launch import free_endpoint
from services.recorder.bridge_watch import check_no_live_bridge
from services.recorder.options import RecorderOptions
from services.recorder.routing import Incoming
from services.recorder.sink import RecordingSink
from shared.bus import Bus, BusConfig, ServiceHost, open_router
from shared.bus.keys import alive_key
from shared.errors import InvalidInputError, ServiceUnavailableError
from shared.messages import Trajectory
from shared.robot import Side
from tests.slow_link import SlowLink

NAMESPACE = "bridgeappears"
#: Trajectories in the recording, and the time between two [s].
COUNT, GAP = 30, 0.1
#: Trajectories that arrive before the bridge comes alive.
BEFORE_BRIDGE = 5


def trajectory(i: int) -> Trajectory:
    """A short trajectory, told from the others by its first angle."""
    n = 5
    rows = [[0.001 * i, -0.1, 0.3, 0.4 + 0.01 * k, 0.0] for k in range(n)]
    zeros = [[0.0] * 5 for _ in range(n)]
    return Trajectory(
        arm=Side.RIGHT,
        joint_names=list(Side.RIGHT.joint_names),
        times=[0.01 * k for k in range(n)],
        positions=rows,
        velocities=zeros,
        accelerations=zeros,
        primitives=["S_R E_P W_P"] * n,
        wrist_path=[(0.1, -0.1, 0.0)] * n,
    )


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


def recorded(path: Path, messages: list[tuple[str, bytes]]) -> Path:
    """``messages`` (relative key, JSON body) recorded ``GAP`` apart."""
    sink = RecordingSink(RecorderOptions(output=path, keys=("**",)), NAMESPACE)
    sink.start()
    start = time.time_ns()
    for i, (key, body) in enumerate(messages):
        t = start + int(i * GAP * 1e9)
        sink.put(Incoming(f"{NAMESPACE}/{key}", body, "application/json", t, t))
    sink.stop()
    return path


def trajectory_json(i: int) -> bytes:
    """:func:`trajectory` as the bridge receives it."""
    return trajectory(i).model_dump_json().encode()


@pytest.fixture(scope="module")
def trajectories_first(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``BEFORE_BRIDGE`` trajectories, then ``COUNT`` ``misc/x`` messages;
    all ``GAP`` apart."""
    first = [("plan/trajectory", trajectory_json(i)) for i in range(BEFORE_BRIDGE)]
    rest = [("misc/x", b"{}")] * COUNT
    return recorded(tmp_path_factory.mktemp("first") / "s.mcap", first + rest)


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``COUNT`` trajectories on ``plan/trajectory``, ``GAP`` apart."""
    messages = [("plan/trajectory", trajectory_json(i)) for i in range(COUNT)]
    return recorded(tmp_path_factory.mktemp("bridge") / "s.mcap", messages)


class Observer:
    """Messages arriving on ``path``, and when this session saw ``service``'s
    token (a bridge's: trajectories; a decide service's: models)."""

    def __init__(
        self, bus: Bus, path: str = "plan/trajectory", service: str = "bridge"
    ) -> None:
        self.got: list[tuple[bytes, float]] = []  # (payload, arrival [s])
        self.bridge_seen: float | None = None
        self._lock = threading.Lock()
        self._sub = bus.session.declare_subscriber(bus.key(path), self._on)
        token = alive_key(NAMESPACE, service)
        self._live = bus.session.liveliness().declare_subscriber(token, self._alive)

    def _on(self, sample: zenoh.Sample) -> None:
        with self._lock:
            self.got.append((sample.payload.to_bytes(), time.monotonic()))

    def angles(self) -> list[float]:
        """The first angle of each trajectory that arrived."""
        read = Trajectory.model_validate_json
        return [read(payload).positions[0][0] for payload, _ in self.got]

    def _alive(self, sample: zenoh.Sample) -> None:
        if sample.kind == zenoh.SampleKind.PUT and self.bridge_seen is None:
            self.bridge_seen = time.monotonic()

    def wait(self, n: int, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while len(self.got) < n and time.monotonic() < deadline:
            time.sleep(0.01)

    def after_bridge(self) -> int:
        """Trajectories that arrived after the token was seen here."""
        assert self.bridge_seen is not None, "the observer never saw the bridge"
        return sum(when > self.bridge_seen for _, when in self.got)

    def close(self) -> None:
        self._sub.undeclare()
        self._live.undeclare()  # type: ignore[no-untyped-call]


def replay_while_a_bridge_starts(
    config: BusConfig,
    path: Path,
    *args: str,
    watched: tuple[str, str] = ("plan/trajectory", "bridge"),
) -> tuple[subprocess.CompletedProcess[str], Observer]:
    """Run ``armplan replay``; start a bridge's token after ``BEFORE_BRIDGE``
    (or ``watched``'s service's, counting its key's messages)."""
    command = [sys.executable, "-m", "armplan", "replay", str(path), *args]
    command += ["--connect", config.endpoint, "--namespace", NAMESPACE]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    path_watched, service = watched
    with Bus.connect(config) as bus, Bus.connect(config) as bridge:
        observer = Observer(bus, path_watched, service)
        try:
            process = subprocess.Popen(
                command,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env=env,
            )
            try:
                observer.wait(BEFORE_BRIDGE, timeout=30)
                assert len(observer.got) >= BEFORE_BRIDGE, "the replay sent nothing"
                with ServiceHost(bridge, service, []):
                    stdout, stderr = process.communicate(timeout=30)
                    time.sleep(0.3)  # anything still on its way arrives
            finally:
                if process.poll() is None:
                    process.kill()
                    process.wait()
        finally:
            observer.close()
    done = subprocess.CompletedProcess(command, process.returncode, stdout, stderr)
    return done, observer


def test_a_bridge_that_comes_alive_stops_an_unkeyed_replay(
    config: BusConfig, recording: Path
) -> None:
    """A bridge's token declared mid-replay: at most the one trajectory in
    flight arrives after it is seen; exit 1 saying how many were sent and
    how many trajectories were held back, and that --keys replays on purpose;
    the summary's count is what arrived."""
    out, observer = replay_while_a_bridge_starts(config, recording)
    assert out.returncode == 1, (out.stdout, out.stderr)
    assert observer.after_bridge() <= 1, observer.got
    sent = len(observer.got)
    assert BEFORE_BRIDGE <= sent < COUNT
    assert out.stdout == (
        f"armplan replay: sent {sent} of {COUNT} messages, then stopped: a "
        f"bridge came alive in namespace {NAMESPACE!r}\n"
    )
    assert out.stderr == (
        f"armplan: error: a bridge came alive in namespace {NAMESPACE!r} during "
        f"the replay: it stopped after {sent} of {COUNT} messages, holding back "
        f"the recorded plan/trajectory ({COUNT - sent} left) (a bridge with "
        "--follow would move the robot again, and they would mix with the live "
        "messages); a message already on its way when the bridge was seen cannot "
        "be recalled. To replay into a live robot on purpose, choose the keys "
        "with --keys, e.g. --keys plan/trajectory --wait-for bridge\n"
    )
    assert observer.angles() == [trajectory(i).positions[0][0] for i in range(sent)]


def test_a_keyed_replay_goes_on_when_a_bridge_comes_alive(
    config: BusConfig, recording: Path
) -> None:
    """--keys plan/trajectory: the user asked, so a bridge coming alive
    mid-replay changes nothing: every trajectory arrives, exit 0."""
    out, observer = replay_while_a_bridge_starts(
        config, recording, "--keys", "plan/trajectory", "--speed", "2"
    )
    assert out.returncode == 0, out.stderr
    assert observer.after_bridge() > 1
    assert len(observer.got) == COUNT
    assert out.stdout.startswith(f"armplan replay: sent {COUNT} of {COUNT} messages")


def test_the_error_says_so_when_no_live_message_was_left(
    config: BusConfig, trajectories_first: Path
) -> None:
    """The bridge comes alive after every recorded trajectory went: the
    replay still stops (nothing more is sent), but does not claim to hold
    back trajectories; it said "holding back the recorded none (a bridge
    with --follow would move the robot again ...)"."""
    out, observer = replay_while_a_bridge_starts(config, trajectories_first)
    assert out.returncode == 1, (out.stdout, out.stderr)
    assert len(observer.got) == BEFORE_BRIDGE
    sent = int(out.stdout.split()[3])
    assert BEFORE_BRIDGE <= sent < BEFORE_BRIDGE + COUNT
    total = BEFORE_BRIDGE + COUNT
    assert out.stderr == (
        f"armplan: error: a bridge came alive in namespace {NAMESPACE!r} during "
        f"the replay: it stopped after {sent} of {total} messages, holding back "
        f"the other {total - sent}; every recorded plan/* and bridge/* message "
        "had been sent before it came alive. To replay the rest, choose its "
        "keys with --keys\n"
    )


@pytest.fixture(scope="module")
def models(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``COUNT`` models on ``fit/model/update``, ``GAP`` apart (bodies numbered:
    the replay sends bytes, whatever they hold)."""
    messages = [("fit/model/update", b'{"i": %d}' % i) for i in range(COUNT)]
    return recorded(tmp_path_factory.mktemp("models") / "s.mcap", messages)


def test_a_decide_service_that_comes_alive_stops_an_unkeyed_replay_of_models(
    config: BusConfig, models: Path
) -> None:
    """A decide service swaps in each fit/model/update it receives: the check
    that refused a recording of models while one was alive was made once,
    and a decide service started mid-replay took the rest of the recorded
    models (the last replaced the model every later plan used). Now it is
    watched as a bridge is: at most the one in flight arrives after its
    token is seen; exit 1 naming what was held back."""
    watched = ("fit/model/update", "decide")
    out, observer = replay_while_a_bridge_starts(config, models, watched=watched)
    assert out.returncode == 1, (out.stdout, out.stderr)
    assert observer.after_bridge() <= 1, observer.got
    sent = len(observer.got)
    assert BEFORE_BRIDGE <= sent < COUNT
    assert [payload for payload, _ in observer.got] == [
        b'{"i": %d}' % i for i in range(sent)
    ]
    assert out.stdout == (
        f"armplan replay: sent {sent} of {COUNT} messages, then stopped: a "
        f"decide service came alive in namespace {NAMESPACE!r}\n"
    )
    assert out.stderr == (
        f"armplan: error: a decide service came alive in namespace {NAMESPACE!r} "
        f"during the replay: it stopped after {sent} of {COUNT} messages, holding "
        f"back the recorded fit/model/update ({COUNT - sent} left) (it would "
        "replace the model the decide service decides with, for every later "
        "plan); a message already on its way when the service was seen cannot "
        "be recalled. To replay it on purpose, choose the keys with --keys, e.g. "
        "--keys fit/model/update\n"
    )


def test_a_router_that_does_not_answer_the_check_refuses_the_replay(
    config: BusConfig,
) -> None:
    """A bridge alive before the replay connects, and the router's answer to
    the check's liveliness query held up (a slow or stalled link): the
    query timed out, Zenoh's "Timeout" reply was skipped as no token, and
    the check let the whole recording go to the bridge (the watch, declared
    without history, does not see a token older than itself). Now the check
    refuses when the router does not answer."""
    port = int(config.endpoint.rsplit(":", 1)[1])
    link = SlowLink(port, bandwidth=1e9)
    through = BusConfig(
        endpoints=(link.url.replace("tcp://", "tcp/"),),
        namespace=NAMESPACE,
        timeout=1.0,  # the check's wait for the router's answer
    )
    try:
        with (
            Bus.connect(config) as bridge,
            ServiceHost(bridge, "bridge", []),
            Bus.connect(through, wait=10) as bus,
        ):
            assert check_no_live_bridge_refuses(bus), "the bridge was not seen"
            link.hold_answers(0)  # the replay's connection: answers held up
            try:
                with pytest.raises(ServiceUnavailableError, match="did not answer"):
                    check_no_live_bridge(bus, ["plan/trajectory"])
            finally:
                link.release_answers(0)
    finally:
        link.close()


def check_no_live_bridge_refuses(bus: Bus) -> bool:
    """Whether the check refuses with an answering router (it must)."""
    try:
        check_no_live_bridge(bus, ["plan/trajectory"])
    except InvalidInputError:
        return True
    return False
