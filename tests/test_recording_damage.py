"""Damaged MCAP files: a clear RecordingError or the readable prefix, nothing else.

Truncations of a small live file and of a chunked one (at every byte near
each record's boundaries, every ``STRIDE``-th byte inside a record), and
seeded random corruption, are read back: without ``recover`` the reader
returns every message or raises ``RecordingError``; with ``recover`` it
returns a prefix of the messages written. Any other exception fails.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np
import pytest

from shared.errors import RecordingError
from shared.messages import PlanRequest, ReachTarget
from shared.recording import MessageWriter, read_records, summarize
from shared.recording.inventory import take_inventory
from shared.recording.metadata import read_metadata
from shared.recording.reader import MAGIC, Recording

N = 12
#: Cuts at every byte this near a record's start or end [bytes]: its opcode,
#: its length field and the first bytes of its content.
NEAR = 24
#: Cuts every this many bytes inside a record (most of one file is the
#: message schema, where each cut is alike) [bytes].
STRIDE = 31


def record_bounds(data: bytes) -> list[int]:
    """Where each MCAP record of ``data`` starts, and where the file ends.

    A record is an opcode (1 byte), a content length (8 bytes, little
    endian) and the content, after the 8-byte magic.
    """
    bounds, at = [len(MAGIC)], len(MAGIC)
    while at + 9 <= len(data) - len(MAGIC):
        at += 9 + int.from_bytes(data[at + 1 : at + 9], "little")
        bounds.append(at)
    return [*bounds, len(data)]


def cut_lengths(data: bytes) -> list[int]:
    """The truncation lengths tried: every byte near a boundary, a stride inside."""
    near = {b + d for b in record_bounds(data) for d in range(-NEAR, NEAR + 1)}
    return sorted(
        length
        for length in near | set(range(1, len(data), STRIDE)) | set(range(1, 16))
        if 1 <= length < len(data)
    )


def write(path: Path, chunked: bool) -> list[bytes]:
    """N PlanRequests on one topic; returns their JSON bytes."""
    messages = [
        PlanRequest(targets=[ReachTarget(position=(0.1, -0.1, 0.01 * i))])
        for i in range(N)
    ]
    with MessageWriter(path, chunked=chunked) as writer:
        writer.add_metadata("armplan", {"namespace": "armplan"})
        for i, m in enumerate(messages):
            writer.write("armplan/plan/request", m, log_time=i, publish_time=i)
    return [m.to_json().encode() for m in messages]


def read(path: Path, recover: bool) -> list[bytes] | RecordingError:
    try:
        return [r.raw for r in read_records(path, recover=recover)]
    except RecordingError as error:
        return error


@pytest.fixture(params=[False, True], ids=["live", "chunked"])
def original(
    request: pytest.FixtureRequest, tmp_path: Path
) -> tuple[bytes, list[bytes]]:
    path = tmp_path / "whole.mcap"
    messages = write(path, chunked=request.param)
    return path.read_bytes(), messages


@pytest.mark.timeout(120)
def test_every_truncation_reads_a_prefix_or_fails_clearly(
    original: tuple[bytes, list[bytes]], tmp_path: Path
) -> None:
    """Cut anywhere: a prefix with recover, else all of it or RecordingError;
    cut inside the magic, nothing was recorded: an error even with recover."""
    data, messages = original
    path = tmp_path / "cut.mcap"
    assert record_bounds(data)[-2] == len(data) - len(MAGIC)  # the footer's end
    for length in cut_lengths(data):
        path.write_bytes(data[:length])
        if length < len(MAGIC):
            with pytest.raises(RecordingError, match="ends inside the MCAP magic"):
                Recording(path)
            assert isinstance(read(path, recover=True), RecordingError)
            continue
        if length % 7 == 0:  # the public functions, on a sample of the lengths
            recovered = read(path, recover=True)
            strict = read(path, recover=False)
            assert isinstance(strict, RecordingError) or strict == messages
            read_metadata(path)  # never raises on damage
        recording = Recording(path)
        got = [r.raw for r in recording]
        assert got == messages[: len(got)], length
        if recording.damage is None:
            assert got == messages, length
        else:
            error = recording.error()
            assert error.readable == len(got), length
            assert str(path) in error.message
        if length % 7 == 0 and not isinstance(recovered, RecordingError):
            assert recovered == got


@pytest.mark.timeout(120)
def test_random_corruption_never_escapes_as_another_exception(
    original: tuple[bytes, list[bytes]], tmp_path: Path
) -> None:
    """Flipped bytes: messages or RecordingError, never a traceback."""
    data, messages = original
    rng = np.random.default_rng(7)
    path = tmp_path / "bad.mcap"
    for _ in range(300):
        damaged = bytearray(data)
        for at in rng.integers(0, len(data), size=rng.integers(1, 4)):
            damaged[at] = int(rng.integers(0, 256))
        path.write_bytes(bytes(damaged))
        for recover in (True, False):
            result = read(path, recover)
            assert isinstance(result, (list, RecordingError))
            if isinstance(result, list):
                assert len(result) <= len(messages)
        with contextlib.suppress(RecordingError):
            take_inventory(path, recover=True, validate=True)


def test_a_killed_writer_leaves_a_readable_prefix(tmp_path: Path) -> None:
    """A live file never closed (no summary) is damaged after all its messages."""
    path = tmp_path / "killed.mcap"
    writer = MessageWriter(path, chunked=False)
    for i in range(5):
        writer.write("t", ReachTarget(position=(0.0, 0.0, i)), log_time=i)
    writer.flush()
    with pytest.raises(RecordingError, match="damaged after 5 readable messages"):
        list(read_records(path))
    assert len(list(read_records(path, recover=True))) == 5
    writer.close()


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "no such file"),
        (b"", r"is empty \(0 bytes\), not an MCAP file: nothing was recorded"),
        (b"hello, this is text\n" * 20, r"is not an MCAP file \(no MCAP magic"),
        (b"hello\n", r"is not an MCAP file \(no MCAP magic"),
        (b"\x89MCA", r"ends inside the MCAP magic \(4 of its 8 bytes\), not an"),
    ],
)
def test_files_that_are_not_recordings(
    tmp_path: Path, content: bytes | None, message: str
) -> None:
    """Missing, empty and non-MCAP files name the file and the problem, also
    when recovering: a file shorter than the MCAP magic was "damaged after 0
    readable messages" (an empty recording with recover), and a longer one
    not MCAP read as empty with read_records or summarize and recover."""
    path = tmp_path / "x.mcap"
    if content is not None:
        path.write_bytes(content)
    for recover in (False, True):
        with pytest.raises(RecordingError, match=message):
            list(read_records(path, recover=recover))
        with pytest.raises(RecordingError, match=message):
            summarize(path, recover=recover)
        with pytest.raises(RecordingError, match=message):
            take_inventory(path, recover=recover)


def test_a_writer_stopped_after_its_magic_left_an_empty_recording(
    tmp_path: Path,
) -> None:
    """The magic, and part of the header: an MCAP file cut short before its
    first message, damaged after 0 messages; recover reads none."""
    path = tmp_path / "x.mcap"
    with MessageWriter(path, chunked=False) as writer:
        writer.write("t", ReachTarget(position=(0.0, 0.0, 1.0)), log_time=1)
    whole = path.read_bytes()
    for cut in (8, 12):
        path.write_bytes(whole[:cut])
        with pytest.raises(RecordingError, match="damaged after 0 readable messages"):
            list(read_records(path))
        assert list(read_records(path, recover=True)) == []
        assert summarize(path, recover=True).channels == {}


def test_a_name_too_long_for_the_file_system_is_a_recording_error() -> None:
    """A 5000-character name (the fit service once answered internal_error)."""
    with pytest.raises(RecordingError, match="File name too long"):
        list(read_records("x" * 5000 + ".mcap"))


def test_a_rotated_recording_named_by_its_stem_points_to_its_parts(
    tmp_path: Path,
) -> None:
    """`-o r.mcap --rotate-size` wrote r-0001.mcap ...: asking for r.mcap says so."""
    for n in (1, 2, 3):
        (tmp_path / f"r-{n:04d}.mcap").write_bytes(b"x")
    with pytest.raises(
        RecordingError,
        match=r"r\.mcap: no such file; the recording was rotated into r-0001\.mcap "
        r"to r-0003\.mcap$",
    ):
        list(read_records(tmp_path / "r.mcap"))


def test_a_folder_is_not_a_recording(tmp_path: Path) -> None:
    """A directory path is refused with a clear message."""
    with pytest.raises(RecordingError, match="is a folder, not an MCAP file"):
        list(read_records(tmp_path))


def _json_messages(path: Path, *messages: bytes) -> Path:
    """A well-formed MCAP file (mcap's writer), ``messages`` on one JSON channel."""
    from mcap.writer import Writer

    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="test")
        channel = writer.register_channel(
            topic="armplan/misc/note", message_encoding="json", schema_id=0
        )
        for i, data in enumerate(messages, start=1):
            writer.add_message(channel, log_time=i, publish_time=i, data=data)
        writer.finish()
    return path


@pytest.mark.parametrize(
    ("data", "why"),
    [
        (b"", "is empty (0 bytes)"),
        (b"[" * 200_000 + b"]" * 200_000, "is JSON nested too deeply to read"),
        (b'{"a": 1', "is not JSON (Expecting ',' delimiter: line 1 column 8 (char 7))"),
    ],
    ids=["empty", "deep", "cut"],
)
def test_a_message_that_is_not_json_is_named(
    tmp_path: Path, data: bytes, why: str
) -> None:
    """Reading stops at it naming the message, its channel and why: a deep
    one was "bytes that are not MCAP records" (a RecursionError), the others
    a bare "a message in it is not UTF-8 JSON"; recover reads those before."""
    path = _json_messages(tmp_path / "x.mcap", b'{"n": 1}', data, b'{"n": 3}')
    with pytest.raises(RecordingError) as raised:
        list(read_records(path))
    assert raised.value.message == (
        f"{path} is damaged after 1 readable message: a message in it is not "
        "UTF-8 JSON: message 2 of the file (channel armplan/misc/note, log time "
        f"2 ns) {why}; --recover (or recover=True) reads that message"
    )
    assert [r.data for r in read_records(path, recover=True)] == [{"n": 1}]
    recording = Recording(path)
    list(recording)
    assert recording.damage_code == "not_json"
