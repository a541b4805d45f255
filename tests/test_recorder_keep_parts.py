"""``--keep-parts``: a rotating live recording keeps only its newest parts.

Real router, real Zenoh sessions, real MCAP files.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from mcap.reader import make_reader
from record_cli import record_command

from armplan.launch import free_endpoint
from services.recorder import RecorderOptions, RecorderProcess
from services.recorder.replay import replay_items
from services.recorder.service import Recorder
from shared.bus import Bus, BusConfig, open_router
from shared.recording.rotation import RotationPolicy, part_path

NAMESPACE = "keeptest"
#: Longest wait for samples to reach the recorder after the last put [s].
SETTLE = 0.5


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


def publish(config: BusConfig, payloads: list[bytes]) -> None:
    """Put ``payloads`` on misc/x once the recorder's subscriber is known."""
    with Bus.connect(config) as bus:
        publisher = bus.session.declare_publisher(
            bus.key("misc/x"), congestion_control=zenoh.CongestionControl.BLOCK
        )
        deadline = time.monotonic() + 5.0
        while not publisher.matching_status.matching:
            assert time.monotonic() < deadline, "no subscriber"
            time.sleep(0.01)
        for payload in payloads:
            publisher.put(payload)
        time.sleep(SETTLE)
        publisher.undeclare()  # type: ignore[no-untyped-call]


def whole(path: Path) -> bool:
    """Whether ``path`` is an MCAP file closed with its summary."""
    with path.open("rb") as stream:
        return make_reader(stream).get_summary() is not None


def test_keep_two_parts_of_six_leaves_the_newest_two_whole(
    config: BusConfig, tmp_path: Path
) -> None:
    """64k parts, keep 2: after 5 rotations the last 2 parts, each whole."""
    out = tmp_path / "s.mcap"
    rotation = RotationPolicy(max_bytes=64 * 1024, keep_parts=2)
    options = RecorderOptions(
        output=out, keys=("misc/*",), rotation=rotation, foxglove=False
    )
    pad = "x" * 16_000
    payloads = [json.dumps({"i": i, "pad": pad}).encode() for i in range(28)]
    with Bus.connect(config) as bus:
        recorder = Recorder(bus, options).start()
        stranger = part_path(out, 9)  # named like a part, not this run's
        stranger.write_bytes(b"an earlier run")
        try:
            publish(config, payloads)
        finally:
            paths = recorder.stop()
    started = len(recorder.sink.pruned) + len(paths)
    assert started == 6, started  # 5 messages a part: 5 rotations
    assert paths == [part_path(out, 5), part_path(out, 6)]
    assert recorder.sink.pruned == [part_path(out, n) for n in range(1, 5)]
    assert sorted(tmp_path.iterdir()) == [*paths, stranger]
    assert stranger.read_bytes() == b"an earlier run"
    for path in paths:
        assert whole(path), path
    kept = [json.loads(item.payload)["i"] for item in replay_items(paths)]
    assert kept == list(range(28 - len(kept), 28))  # the newest, in order
    note = recorder.sink.files_note()  # after "28 messages in": not in 5 and 6
    assert note == (
        f"6 parts, the newest 2 kept: {paths[0]}, {paths[1]} "
        "(4 older parts removed, --keep-parts 2)"
    ), note


def run(command: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        command, capture_output=True, text=True, timeout=60, check=False
    )


def test_keep_parts_without_rotation_is_a_usage_error(
    config: BusConfig, tmp_path: Path
) -> None:
    """Both commands exit 2 naming --rotate-size and --rotate-duration."""
    out = tmp_path / "s.mcap"
    recorder = [sys.executable, "-m", "services.recorder", "-o", str(out)]
    for command in (
        [*recorder, "--connect", config.endpoint, "--keep-parts", "2"],
        record_command(config, out, "--keep-parts", "2"),
    ):
        done = run(command)
        assert done.returncode == 2, done.stderr
        assert "--keep-parts needs --rotate-size or --rotate-duration" in done.stderr
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("keep", ["0", "-1", "1.5", "two"])
def test_a_bad_keep_parts_is_refused_naming_the_option(
    config: BusConfig, tmp_path: Path, keep: str
) -> None:
    """Not a whole number of at least 1: exit 1, the error names --keep-parts."""
    out = tmp_path / "s.mcap"
    done = run(
        record_command(config, out, "--rotate-size", "64k", f"--keep-parts={keep}")
    )
    assert done.returncode == 1, done.stderr
    assert (
        f"--keep-parts must be a whole number of files, at least 1, got {keep!r}"
        in (done.stderr)
    )
    assert "Traceback" not in done.stderr
    assert not list(tmp_path.iterdir())


def test_a_recorder_process_keeps_parts_and_logs_each_removal(
    config: BusConfig, tmp_path: Path
) -> None:
    """RecorderProcess passes --keep-parts on; its paths are the parts left."""
    out = tmp_path / "p.mcap"
    rotation = RotationPolicy(max_bytes=64 * 1024, keep_parts=3)
    options = RecorderOptions(rotation=rotation, foxglove=False)
    pad = "x" * 16_000
    log = tmp_path / "recorder.log"
    with (
        log.open("w") as stream,
        RecorderProcess.start(
            config, out, keys=["misc/*"], options=options, log=stream
        ) as recorder,
    ):
        publish(config, [json.dumps({"i": i, "pad": pad}).encode() for i in range(28)])
    assert recorder.paths == [part_path(out, n) for n in (4, 5, 6)]
    assert sorted(tmp_path.glob("p-*.mcap")) == recorder.paths
    said = log.read_text()
    for n in (1, 2, 3):
        assert f"removed old part {part_path(out, n)} (" in said, said
    assert "(3 older parts removed, --keep-parts 3)" in said, said
