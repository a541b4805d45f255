"""A replay on the secured router says which messages its login may not publish.

`armplan replay` with the client's file printed "sent 3 of 3 messages" and
exited 0 while the router dropped every one (only a topic's publisher may
put it). Now it warns, naming the topics and whose they are, before sending;
with the planner's file the planner's keys go through, without a warning.
Keys outside the catalogue (a file another tool wrote), which no process
may publish, are warned of too. A replay of which the router would drop every
message (another --namespace than the login file's, whose namespace the
rules name; or only keys its login may not publish) said "sent" and exited
0: it now exits 1 before sending, saying why.
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
from mcap.writer import Writer
from native_processes import Native

from armplan.launch import catalog, free_endpoint
from armplan.secure import TEMPLATE, AccessControl, Bundle, write_bundle
from services.recorder import RecorderProcess
from services.recorder.replay_login import refused_by_rules
from shared.bus import Bus, BusConfig, load_config, open_router
from shared.bus.topics import TOPICS

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
        self.keys: list[str] = []
        self._lock = threading.Lock()
        self._sub = bus.session.declare_subscriber("armplan/**", self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        with self._lock:
            self.payloads.append(sample.payload.to_bytes())
            self.keys.append(str(sample.key_expr))

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
        done = replay(
            recording,
            *("--keys", "plan/trajectory", "--config", str(planner)),
            *("--namespace", "armplan"),  # the file's: passes
        )
        assert done.returncode == 0, done.stderr
        assert "warning" not in done.stderr
        assert inbox.wait(2, 20.0) == [MESSAGES[0][1], MESSAGES[2][1]]

        done = replay(recording, "--config", str(planner), "--wait", "30")
        assert done.returncode == 0, done.stderr
        assert done.stderr == (
            f"armplan replay: warning: {planner} logs in as user 'planner', which "
            "the secured router's rules do not let publish bridge/state (1 "
            "message, bridge's): the router drops those messages without a "
            "word. Replay each publisher's keys with its own file, e.g. --keys "
            "bridge/state --config DIR/bridge.json5, or replay into an "
            "unsecured router\n"
        )
        assert done.stdout.startswith("armplan replay: sent 3 of 3 messages")
        assert done.stdout.endswith(
            "; a secured router drops the 1 user 'planner' may not publish\n"
        )
        assert len(inbox.wait(5, QUIET)) == 4  # the trajectories, not the state


@pytest.mark.parametrize(
    ("user", "keys", "chosen"),
    [
        ("client", [], "every message"),
        ("planner", ["--keys", "bridge/state"], "every message --keys keeps"),
    ],
    ids=["client", "planner-bridge-keys"],
)
def test_a_replay_its_login_may_publish_nothing_of_is_refused(
    recording: pathlib.Path, secured: Bundle, user: str, keys: list[str], chosen: str
) -> None:
    """The client's file (which publishes nothing), or the planner's with
    --keys keeping only the bridge's state: exit 1 before sending (it said
    "sent" and exited 0), naming the keys and whose they are."""
    recorder = load_config(secured.clients["recorder"])
    with Bus.connect(recorder, wait=30) as bus:
        inbox = Inbox(bus)
        login = secured.clients[user]
        done = replay(recording, *keys, "--config", str(login), "--wait", "30")
        assert done.returncode == 1, done.stderr
        trajectories = "plan/trajectory (2 messages, planner's), " if not keys else ""
        assert done.stderr == (
            f"armplan: error: {login} logs in as user {user!r}, which the secured "
            f"router's rules do not let publish {trajectories}bridge/state (1 "
            f"message, bridge's): the router would drop {chosen} without a word, "
            "so none is sent. Replay each publisher's keys with its own file, "
            f"e.g. --keys {'bridge/state' if keys else 'plan/trajectory'} --config "
            f"DIR/{'bridge' if keys else 'planner'}.json5, or replay into an "
            "unsecured router\n"
        )
        assert done.stdout == ""
        assert inbox.wait(1, QUIET) == []


def test_a_replay_under_another_namespace_than_its_logins_is_refused(
    recording: pathlib.Path, secured: Bundle
) -> None:
    """The planner's file (namespace armplan, which the rules name) with
    --namespace nao1: the router dropped every message and the replay exited
    0; now exit 1 before sending, naming both namespaces."""
    recorder = load_config(secured.clients["recorder"])
    with Bus.connect(recorder, wait=30) as bus:
        inbox = Inbox(bus)
        planner = secured.clients["planner"]
        done = replay(
            recording,
            *("--keys", "plan/trajectory", "--config", str(planner)),
            *("--namespace", "nao1", "--wait", "30"),
        )
        assert done.returncode == 1, done.stderr
        assert done.stderr == (
            f"armplan: error: {planner} logs in as user 'planner', whose file "
            "was made for the namespace 'armplan', the only one the secured "
            "router's rules name, but the replay publishes under --namespace "
            "'nao1': the router would drop every message without a word, so "
            "none is sent. Replay under 'armplan' (leave out --namespace), with "
            "a login file made for 'nao1' (`armplan certs --namespace nao1`) on "
            "that namespace's router, or into an unsecured router\n"
        )
        assert done.stdout == ""
        assert inbox.wait(1, QUIET) == []


#: Keys to check the replay's reading of the rules on: every topic, keys
#: outside the catalogue (under a publisher's subtree and not), a doubled one.
RULE_KEYS = [
    *(topic.path for topic in TOPICS),
    "bridge",
    "bridge/other",
    "plan/other",
    "fit/model",
    "misc/raw",
    "armplan/plan/trajectory",
]


def test_the_replays_reading_of_the_rules_is_the_routers() -> None:
    """Which keys refused_by_rules refuses each user is what the router's
    rules (config/secure/router.json5) refuse it; keys outside the catalogue
    were not judged (all passed, the router dropped most)."""
    acl = AccessControl.from_file(TEMPLATE)
    for user in acl.usernames():
        refused = refused_by_rules(dict.fromkeys(RULE_KEYS, 1), user)
        for path in RULE_KEYS:
            allowed = acl.allows(user, "put", "ingress", f"armplan/{path}")
            assert (path not in refused) is allowed, (user, path)


def test_a_foreign_file_is_published_on_its_keys_with_a_warning_for_the_rest(
    secured: Bundle, tmp_path: pathlib.Path
) -> None:
    """A file the mcap library wrote, with topics armplan/plan/trajectory and
    misc/raw and no armplan metadata, replayed with the planner's file: the
    trajectories reach armplan/plan/trajectory (they went to
    armplan/armplan/plan/trajectory, which the router dropped without a
    warning); misc/raw, which no process may publish, is warned of."""
    path = tmp_path / "foreign.mcap"
    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="another tool")
        ids = {
            topic: writer.register_channel(topic, "json", schema_id=0)
            for topic in ("armplan/plan/trajectory", "misc/raw")
        }
        topics = ["armplan/plan/trajectory", "misc/raw", "armplan/plan/trajectory"]
        for i, topic in enumerate(topics):
            t = 10**18 + i * 10**7
            writer.add_message(ids[topic], t, b'{"foreign": %d}' % i, t)
        writer.finish()
    recorder = load_config(secured.clients["recorder"])
    with Bus.connect(recorder, wait=30) as bus:
        inbox = Inbox(bus)
        planner = secured.clients["planner"]
        done = replay(path, "--config", str(planner), "--wait", "30")
        assert done.returncode == 0, done.stderr
        assert done.stderr == (
            f"armplan replay: warning: {planner} logs in as user 'planner', which "
            "the secured router's rules do not let publish misc/raw (1 message, "
            "no process's): the router drops those messages without a word. "
            "Choose with --keys the keys to keep, without those no process may "
            "publish, or replay into an unsecured router\n"
        )
        assert done.stdout.startswith("armplan replay: sent 3 of 3 messages")
        assert inbox.wait(3, QUIET) == [b'{"foreign": 0}', b'{"foreign": 2}']
        assert inbox.keys == ["armplan/plan/trajectory"] * 2
