"""A file another tool wrote is replayed on its own keys, not under the namespace twice.

Armplan's recorder notes its namespace in the file; a file written with the
``mcap`` library by another tool notes none. Its topic
``armplan/plan/trajectory`` was taken as relative and published on
``armplan/armplan/plan/trajectory`` ("sent 3 of 3", exit 0, nobody
listening there). Now a topic under the replay's namespace is a full key
in it, published unchanged; any other topic is relative, as before. Real
MCAP files from the ``mcap`` library; a real router and a subscriber to
every key (``**``) in this test; ``armplan replay`` a real process.
"""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from mcap.writer import Writer
from native_processes import ROOT

from armplan.launch import free_endpoint
from services.recorder.replay import replay_items
from shared.bus import Bus, BusConfig, open_router
from shared.bus.keys import alive_key

NAMESPACE = "foreignns"
#: (topic, payload) of the foreign file, 0.05 s apart.
MESSAGES = [
    (f"{NAMESPACE}/plan/trajectory", b'{"i": 0}'),
    ("plan/decision", b'{"i": 1}'),
    (f"{NAMESPACE}/plan/trajectory", b'{"i": 2}'),
    ("misc/raw", b'{"i": 3}'),
    (f"other/{NAMESPACE}/x", b'{"i": 4}'),
]


def foreign_file(
    path: Path, messages: list[tuple[str, bytes]], spacing: float = 0.05
) -> Path:
    """``messages`` (topic, payload) written with the ``mcap`` library,
    ``spacing`` [s] apart: JSON, no schema, no armplan metadata."""
    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="another tool")
        channels: dict[str, int] = {}
        for i, (topic, payload) in enumerate(messages):
            if topic not in channels:
                channels[topic] = writer.register_channel(
                    topic=topic, message_encoding="json", schema_id=0
                )
            t = 10**18 + i * round(spacing * 1e9)
            writer.add_message(
                channel_id=channels[topic], log_time=t, data=payload, publish_time=t
            )
        writer.finish()
    return path


def numbered(topics: list[str]) -> list[tuple[str, bytes]]:
    """Each topic with the payload ``{"i": <its index>}``."""
    return [(topic, b'{"i": %d}' % i) for i, topic in enumerate(topics)]


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


class Everything:
    """(key, payload) of every put on the bus, whatever its key."""

    def __init__(self, bus: Bus) -> None:
        self.got: list[tuple[str, bytes]] = []
        self._lock = threading.Lock()
        self._sub = bus.session.declare_subscriber("**", self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        with self._lock:
            self.got.append((str(sample.key_expr), sample.payload.to_bytes()))

    def wait(self, count: int, timeout: float) -> list[tuple[str, bytes]]:
        deadline = time.monotonic() + timeout
        while len(self.got) < count and time.monotonic() < deadline:
            time.sleep(0.02)
        return list(self.got)


def test_a_foreign_files_keys_under_the_namespace_go_out_unchanged(
    config: BusConfig, tmp_path: Path
) -> None:
    """Keys under the namespace as recorded, the others under it; exit 0."""
    path = foreign_file(tmp_path / "foreign.mcap", MESSAGES)
    with Bus.connect(config) as bus:
        everything = Everything(bus)
        done = run(replay_command(path, config))
        assert done.returncode == 0, done.stderr
        everything.wait(len(MESSAGES), 10.0)
        time.sleep(0.5)  # nothing more comes
        got = list(everything.got)
    assert got == [
        (f"{NAMESPACE}/plan/trajectory", b'{"i": 0}'),
        (f"{NAMESPACE}/plan/decision", b'{"i": 1}'),
        (f"{NAMESPACE}/plan/trajectory", b'{"i": 2}'),
        (f"{NAMESPACE}/misc/raw", b'{"i": 3}'),
        (f"{NAMESPACE}/other/{NAMESPACE}/x", b'{"i": 4}'),
    ]


def test_keys_of_a_foreign_file_are_relative_to_the_replays_namespace(
    tmp_path: Path,
) -> None:
    """--keys and the recorded keys name them relative to the namespace;
    under another namespace the file's topics are all relative."""
    path = foreign_file(tmp_path / "foreign.mcap", MESSAGES)
    items = replay_items(path, namespace=NAMESPACE)
    assert items.recorded == [
        "misc/raw",
        f"other/{NAMESPACE}/x",
        "plan/decision",
        "plan/trajectory",
    ]
    chosen = replay_items(path, keys=["plan/trajectory"], namespace=NAMESPACE)
    assert [item.payload for item in chosen] == [b'{"i": 0}', b'{"i": 2}']
    elsewhere = replay_items(path, namespace="nao1")
    assert f"{NAMESPACE}/plan/trajectory" in elsewhere.recorded


def test_a_recorded_wildcard_key_is_not_put_into_a_live_bridge(
    config: BusConfig, tmp_path: Path
) -> None:
    """A topic ``*/trajectory`` (another tool's file, or a put on a wildcard
    that armplan's recorder recorded) went out as ``<ns>/*/trajectory``,
    which reaches the bridge's ``<ns>/plan/trajectory`` subscriber: the
    live-bridge check, which looks at the first chunk, let it through and
    a bridge with --follow played it (exit 0). A put on a wildcard reaches
    every key it matches, so such a key is refused before anything is
    sent, as a key that is not a Zenoh key is; --keys leave it out."""
    topics = ["misc/raw", "*/trajectory", "**"]
    path = foreign_file(tmp_path / "wild.mcap", numbered(topics), spacing=0.01)
    command = replay_command(path, config)
    with Bus.connect(config) as bus:
        token = bus.session.liveliness().declare_token(alive_key(NAMESPACE, "bridge"))
        everything = Everything(bus)
        try:
            done = run(command)
            chosen = run([*command, "--keys", "misc/**"])
            everything.wait(1, 10.0)
            time.sleep(0.5)  # nothing more comes
        finally:
            token.undeclare()  # type: ignore[no-untyped-call]
        got = list(everything.got)
    assert done.returncode == 1, done.stdout
    assert "its channel '*/trajectory' is not a Zenoh key" in done.stderr
    assert "no wildcard" in done.stderr
    assert chosen.returncode == 0, chosen.stderr
    assert got == [(f"{NAMESPACE}/misc/raw", b'{"i": 0}')]


def replay_command(path: Path, config: BusConfig) -> list[str]:
    """``armplan replay`` of ``path`` onto the test's router and namespace."""
    command = [sys.executable, "-m", "armplan", "replay", str(path)]
    return [*command, "--connect", config.endpoint, "--namespace", NAMESPACE]


def run(command: list[str]) -> subprocess.CompletedProcess[str]:
    """``command`` run with this repository's code; its output as text."""
    return subprocess.run(
        command,
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )


def test_a_recorded_model_is_not_replayed_into_a_live_decide_service(
    config: BusConfig, tmp_path: Path
) -> None:
    """A recording holding fit/model/update (fit publishes its model at start,
    and after each fit) replayed without --keys into `armplan up` swapped
    the live decide service's model for the recorded one ("swapped in model
    ... from armplan/fit/model/update"), exit 0: every later plan was
    decided with it, while fit served another. With a decide service alive
    it is refused before anything is sent, naming the key; --keys sends it
    on purpose."""
    topics = ["misc/raw", "fit/model/update"]
    path = foreign_file(tmp_path / "model.mcap", numbered(topics), spacing=0.01)
    command = replay_command(path, config)
    with Bus.connect(config) as bus:
        token = bus.session.liveliness().declare_token(alive_key(NAMESPACE, "decide"))
        everything = Everything(bus)
        try:
            done = run(command)
            time.sleep(0.5)  # nothing comes
            refused = list(everything.got)
            chosen = run([*command, "--keys", "fit/model/update"])
            everything.wait(1, 10.0)
        finally:
            token.undeclare()  # type: ignore[no-untyped-call]
        got = list(everything.got)
    assert done.returncode == 1, done.stdout
    assert (
        f"a decide service is alive in namespace {NAMESPACE!r}: the recorded "
        "fit/model/update would replace the model it decides with"
    ) in " ".join(done.stderr.split())
    assert refused == []
    assert chosen.returncode == 0, chosen.stderr
    assert got == [(f"{NAMESPACE}/fit/model/update", b'{"i": 1}')]


@pytest.mark.parametrize(
    ("spacing", "said"),
    [
        (2 * 365.25 * 86400, "takes 8 years (2.52461e+08 s at speed 1)"),
        (5400.0, "takes 6 hours (21600 s at speed 1)"),
        (901.0, "takes 1 hour (3604 s at speed 1)"),
    ],
)
def test_a_replay_that_would_take_years_says_so_at_once(
    config: BusConfig, tmp_path: Path, spacing: float, said: str
) -> None:
    """Another tool's file whose log times are years apart (two clocks)
    replayed with no word, silent for years between two messages. A replay
    over an hour is announced with its length (here 5 messages ``spacing``
    [s] apart: 4 gaps), before the first is sent; Ctrl-C ends it (130)."""
    path = foreign_file(tmp_path / "long.mcap", MESSAGES, spacing=spacing)
    process = subprocess.Popen(
        replay_command(path, config),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    lines: queue.Queue[str] = queue.Queue()
    stream = process.stderr
    assert stream is not None
    threading.Thread(target=lambda: lines.put(stream.readline()), daemon=True).start()
    try:
        line = lines.get(timeout=30)  # the old code said nothing (for years)
        process.send_signal(signal.SIGINT)
        process.wait(timeout=30)
        rest = stream.read()
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert line.startswith(f"armplan replay: warning: this replay {said}"), line
    assert "--speed shortens it, Ctrl-C stops it" in line
    assert process.returncode == 130, rest
