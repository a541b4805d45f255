"""A recording still being written is never replaced, even with --overwrite.

Two real recorder processes on one real router: the second, given the
first's file (or rotating name) and ``--overwrite``, is refused with one
line naming the file, and the first's recording is whole afterwards, every
message in order. It used to truncate the first's file (or remove its
parts and truncate the one being written) and both exited 0.
"""

from __future__ import annotations

import json
import os
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from record_cli import record_command

from armplan.launch import free_endpoint
from services.recorder import RecorderOptions, RecorderProcess
from services.recorder.replay import replay_items
from shared.bus import Bus, BusConfig, open_router
from shared.errors import RecordingError
from shared.recording import read_records
from shared.recording.rotation import RotatingWriter, RotationPolicy, part_path
from shared.recording.writer import MessageWriter

NS = "reconewriter"
#: Longest wait for samples to reach the recorder after the last put [s].
SETTLE = 0.5


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NS)
    with open_router(config):
        yield config


def publish(config: BusConfig, numbers: range) -> None:
    """Put ``{"i": n, "pad": ...}`` on misc/a for each of ``numbers`` (about 500 B)."""
    with Bus.connect(config) as bus:
        publisher = bus.session.declare_publisher(
            bus.key("misc/a"), congestion_control=zenoh.CongestionControl.BLOCK
        )
        for n in numbers:
            publisher.put(json.dumps({"i": n, "pad": "x" * 500}).encode())
            time.sleep(0.005)
        publisher.undeclare()
    time.sleep(SETTLE)


def second_recorder(config: BusConfig, out: Path, *extra: str) -> tuple[int, str]:
    """``armplan record -o out --overwrite ...``: its exit code and stderr."""
    process = subprocess.run(
        record_command(config, out, "--overwrite", "--duration", "2", *extra),
        capture_output=True,
        text=True,
        env={**os.environ, "ARMPLAN_ZENOH_CONFIG": ""},
        timeout=60,
        check=False,
    )
    return process.returncode, process.stderr


def numbers_in(paths: list[Path]) -> list[int]:
    return [
        r.data["i"] for p in paths for r in read_records(p) if r.topic.endswith("/a")
    ]


def test_overwrite_refuses_the_file_a_recorder_is_writing(
    config: BusConfig, tmp_path: Path
) -> None:
    """B --overwrite on A's live file: exit 1 naming it; A's file keeps all."""
    out = tmp_path / "live.mcap"
    first = RecorderProcess.start(config, out, keys=["misc/*"])
    try:
        publish(config, range(20))
        code, stderr = second_recorder(config, out)
        publish(config, range(20, 40))
    finally:
        paths = first.stop()
    assert code == 1, stderr
    assert stderr == (
        f"armplan: error: {out} is being written by another recorder: give "
        "another name (--overwrite never replaces a recording still being "
        "written)\n"
    )
    assert paths == [out]
    assert numbers_in(paths) == list(range(40))


def test_overwrite_refuses_the_parts_a_rotating_recorder_writes(
    config: BusConfig, tmp_path: Path
) -> None:
    """With rotation, B removes none of A's parts (the first, closed one
    included) and empties none; A's parts replay as one recording."""
    out = tmp_path / "live.mcap"
    options = RecorderOptions(rotation=RotationPolicy(max_bytes=4000), foxglove=False)
    first = RecorderProcess.start(config, out, keys=["misc/*"], options=options)
    try:
        publish(config, range(30))
        assert part_path(out, 3).exists()  # A is past its first parts
        code, stderr = second_recorder(config, out, "--rotate-size", "4000")
        publish(config, range(30, 60))
    finally:
        paths = first.stop()
    assert code == 1, stderr
    error = stderr[stderr.find("armplan: error:") :]  # after the size's warning
    assert error.startswith(
        f"armplan: error: {part_path(out, 1)} is being written by another recorder"
    ), stderr
    assert len(paths) > 3
    assert numbers_in(paths) == list(range(60))
    assert len(replay_items(paths)) == 60


def test_a_closed_recording_is_replaced_by_a_new_file(tmp_path: Path) -> None:
    """Once its writer closed it, --overwrite replaces the file by a new one
    (unlinked, not emptied: a reader that has it open still reads it whole)."""
    out = tmp_path / "s.mcap"
    with MessageWriter(out, chunked=False, overwrite=False) as writer:
        with pytest.raises(RecordingError, match="being written by another"):
            MessageWriter(out, chunked=False, overwrite=True)
        writer.add_metadata("armplan", {"part": "1"})
    old = out.read_bytes()
    with out.open("rb") as reader:
        MessageWriter(out, chunked=False, overwrite=True).close()
        assert reader.read() == old
    assert out.read_bytes() != old


def test_numbered_files_are_removed_all_or_none(tmp_path: Path) -> None:
    """A rotating writer held by another: --overwrite removes no part."""
    path = tmp_path / "r.mcap"
    policy = RotationPolicy(max_bytes=10_000)
    for n in (2, 3):
        part_path(path, n).write_bytes(b"old")
    with MessageWriter(part_path(path, 4), chunked=False, overwrite=False):
        with pytest.raises(RecordingError, match=r"r-0004\.mcap is being written"):
            RotatingWriter(path, policy, overwrite=True).open()
        assert [p.name for p in sorted(tmp_path.iterdir())] == [
            "r-0002.mcap",
            "r-0003.mcap",
            "r-0004.mcap",
        ]


def test_overwrite_on_a_dangling_link_says_so(tmp_path: Path) -> None:
    """--overwrite where a symbolic link points to nothing: refused naming
    the link and its missing target (it used to say the file was being
    written by another recorder); nothing is created where it points."""
    out = tmp_path / "out.mcap"
    target = tmp_path / "gone" / "away.mcap"
    out.symlink_to(target)
    with pytest.raises(RecordingError) as refused:
        MessageWriter(out, chunked=False, overwrite=True)
    print(f"\n{refused.value.message}")
    assert "symbolic link" in refused.value.message
    assert str(target) in refused.value.message
    assert "another recorder" not in refused.value.message
    assert out.is_symlink() and not target.exists()


def test_a_recording_being_written_is_named_so_without_overwrite(
    tmp_path: Path,
) -> None:
    """A second recorder on the first's -o, without --overwrite, was told the
    file 'exists: give another name, or --overwrite to replace it' (rotating:
    'of an earlier recording exists'), and --overwrite was then refused: it
    is being written by another recorder, as it now says at once."""
    out = tmp_path / "s.mcap"
    with (
        MessageWriter(out, chunked=False, overwrite=False),
        pytest.raises(RecordingError) as refused,
    ):
        MessageWriter(out, chunked=False, overwrite=False)
    assert "being written by another recorder" in refused.value.message
    assert "--overwrite to replace" not in refused.value.message
    with pytest.raises(RecordingError, match="exists: give another name, or --ov"):
        MessageWriter(out, chunked=False, overwrite=False)  # closed: an old one

    path = tmp_path / "r.mcap"
    policy = RotationPolicy(max_bytes=10_000)
    first = RotatingWriter(path, policy, overwrite=False).open()
    try:
        with pytest.raises(RecordingError) as refused:
            RotatingWriter(path, policy, overwrite=False).open()
    finally:
        first.close()
    assert refused.value.message.startswith(
        f"{part_path(path, 1)} is being written by another recorder"
    )
    with pytest.raises(RecordingError, match="of an earlier recording exists"):
        RotatingWriter(path, policy, overwrite=False).open()
