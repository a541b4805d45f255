"""A ``--rotate-size`` below what a part weighs alone is warned about, not refused.

With ``--rotate-size 1k`` every message started a new file (an empty part
already weighs 8690 bytes with the Foxglove channels) and nothing said so.
A real router, real recorder processes (``python -m services.recorder`` and
``armplan record``, which share the options) and the MCAP files they write.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest

from armplan.launch import free_endpoint
from services.recorder import RecorderProcess
from services.recorder.duration_floor import duration_note
from services.recorder.options import RecorderOptions
from services.recorder.replay import replay_items
from services.recorder.size_floor import EMPTY_PART, size_note
from shared.bus import BusConfig, open_router
from shared.recording.rotation import RotationPolicy
from tests.record_cli import record_command, start_recording
from tests.test_recorder import publish_all

WARNING = "is less than a part needs"
PAYLOADS = [("misc/x", json.dumps({"i": i}).encode()) for i in range(5)]


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace="floortest")
    with open_router(config):
        yield config


def record_with(config: BusConfig, out: Path, max_bytes: int) -> tuple[list[Path], str]:
    """Run ``python -m services.recorder`` rotating at ``max_bytes`` while
    ``PAYLOADS`` are published; its files and its log."""
    log_path = out.with_suffix(".log")
    options = RecorderOptions(rotation=RotationPolicy(max_bytes=max_bytes))
    with log_path.open("w") as log:
        recorder = RecorderProcess.start(
            config, out, keys=["misc/*"], options=options, log=log
        )
        try:
            publish_all(config, PAYLOADS)
        finally:
            paths = recorder.stop()
    return paths, log_path.read_text()


def record_cli(config: BusConfig, out: Path, *options: str) -> str:
    """Run ``armplan record -o out OPTIONS`` for 3 s while ``PAYLOADS`` are
    published; check it exits 0 with every payload in its parts; its stderr."""
    process = start_recording(record_command(config, out, *options, "--duration", "3"))
    try:
        publish_all(config, PAYLOADS)
        _, stderr = process.communicate(timeout=60)
    finally:
        process.kill()
        process.wait(30)
    assert process.returncode == 0, stderr
    parts = sorted(out.parent.glob(f"{out.stem}-*.mcap"))
    assert [(item.path, item.payload) for item in replay_items(parts)] == PAYLOADS
    return stderr


def test_a_tiny_size_is_warned_about_and_still_recorded(
    config: BusConfig, tmp_path: Path
) -> None:
    paths, log = record_with(config, tmp_path / "tiny.mcap", 1024)
    [line] = [line for line in log.splitlines() if WARNING in line]
    assert "WARNING recorder: --rotate-size 1024 (1024 bytes) is less" in line
    assert f"an empty part already weighs {EMPTY_PART[True]} bytes" in line
    assert "a sane size is at least 1M (recording as asked)" in line
    recorded = [(item.path, item.payload) for item in replay_items(paths)]
    assert recorded == PAYLOADS
    assert len(paths) == 1 + len(PAYLOADS)  # a file per message: as warned
    # the first part, past the size before any message, holds what every
    # part holds on its own: the weight the warning states
    assert abs(paths[0].stat().st_size - EMPTY_PART[True]) < 0.2 * EMPTY_PART[True]


def test_a_normal_size_is_not_warned_about(config: BusConfig, tmp_path: Path) -> None:
    paths, log = record_with(config, tmp_path / "normal.mcap", 10 * 1024**2)
    assert WARNING not in log
    assert len(paths) == 1
    assert [(item.path, item.payload) for item in replay_items(paths)] == PAYLOADS


@pytest.mark.parametrize(
    ("size", "extra", "warned"),
    [
        (
            "1k",
            ["--no-foxglove"],
            "(1024 bytes) is less than a part needs: an "
            "empty part already weighs 684 bytes with --no-foxglove",
        ),
        (
            "100",
            [],
            "(100 bytes) is less than a part needs: an empty part "
            f"already weighs {EMPTY_PART[True]} bytes with the Foxglove channels",
        ),
        ("10M", [], None),
    ],
)
def test_armplan_record_warns_on_stderr_and_records(
    config: BusConfig, tmp_path: Path, size: str, extra: list[str], warned: str | None
) -> None:
    stderr = record_cli(config, tmp_path / "cli.mcap", "--rotate-size", size, *extra)
    if warned is None:
        assert WARNING not in stderr
        return
    [line] = [line for line in stderr.splitlines() if WARNING in line]
    assert line.startswith(f"recorder: --rotate-size {size} {warned}")


def test_a_one_byte_size_is_named_in_the_singular() -> None:
    """--rotate-size 1 was warned about as "(1 bytes)"."""
    note = size_note("1", 1, foxglove=True)
    assert note is not None
    assert note.startswith("recorder: --rotate-size 1 (1 byte) is less than a part")
    assert "(2 bytes)" in (size_note("2", 2, foxglove=False) or "")


def test_a_rotation_under_a_second_is_warned_about_and_still_recorded(
    config: BusConfig, tmp_path: Path
) -> None:
    """``--rotate-duration 0.01`` made 73 files in 8 s with no word: warned
    on stderr, recorded as asked, every message kept."""
    stderr = record_cli(config, tmp_path / "quick.mcap", "--rotate-duration", "0.5")
    assert (
        "recorder: --rotate-duration 0.5 starts a new file every 0.5 s, up to 7200 "
        "files an hour" in stderr
    )


@pytest.mark.parametrize(
    ("seconds", "warned"), [(0.999, True), (1.0, False), (60.0, False)]
)
def test_only_a_rotation_under_a_second_is_warned_about(
    seconds: float, warned: bool
) -> None:
    assert (duration_note(seconds) is not None) is warned
