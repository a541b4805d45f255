"""Rotating live recordings: numbered files, each complete, nothing lost."""

from __future__ import annotations

import fcntl
import time
from pathlib import Path

import pytest
from mcap.reader import make_reader

from shared.errors import InvalidInputError, RecordingError
from shared.recording import read_records
from shared.recording.rotation import (
    RotatingWriter,
    RotationPolicy,
    numbered_parts,
    part_path,
    parts_named,
)
from shared.recording.writer import MessageWriter

SCHEMA = {"type": "object"}


def payload(i: int) -> bytes:
    return b'{"i":%d,"pad":"%s"}' % (i, b"x" * 100)


def read_all(paths: list[Path]) -> list[int]:
    return [r.data["i"] for p in paths for r in read_records(p) if r.topic == "t"]


def has_summary(path: Path) -> bool:
    with path.open("rb") as stream:
        return make_reader(stream).get_summary() is not None


def test_no_limit_writes_exactly_the_path(tmp_path: Path) -> None:
    """Without a limit, one file at the path given."""
    path = tmp_path / "s.mcap"
    with RotatingWriter(path) as writer:
        for i in range(10):
            writer.write("t", "json", SCHEMA, payload(i), i, i)
    assert writer.paths == [path]
    assert read_all([path]) == list(range(10))


def test_size_rotation_numbers_files_and_keeps_every_message(tmp_path: Path) -> None:
    """Files hold about max_bytes each; together every message, in order."""
    opened: list[int] = []

    def on_open(writer: MessageWriter, number: int) -> None:
        opened.append(number)
        writer.add_metadata("armplan", {"part": str(number)})

    path = tmp_path / "s.mcap"
    with RotatingWriter(path, RotationPolicy(max_bytes=2000), on_open) as writer:
        for i in range(60):
            writer.write("t", "json", SCHEMA, payload(i), i, i)
    assert len(writer.paths) > 2
    assert writer.paths == [part_path(path, n) for n in range(1, len(opened) + 1)]
    assert writer.paths[0].name == "s-0001.mcap"
    assert opened == list(range(1, len(writer.paths) + 1))
    assert read_all(writer.paths) == list(range(60))
    for p in writer.paths:
        assert has_summary(p), p
        assert p.stat().st_size < 2000 + 2000  # the limit plus one message and summary


def test_duration_rotation(tmp_path: Path) -> None:
    """A file open for max_seconds is closed before the next message."""
    path = tmp_path / "s.mcap"
    with RotatingWriter(path, RotationPolicy(max_seconds=0.05)) as writer:
        for i in range(6):
            writer.write("t", "json", SCHEMA, payload(i), i, i)
            time.sleep(0.03)
    assert 2 <= len(writer.paths) <= 6
    assert read_all(writer.paths) == list(range(6))


def test_open_creates_the_first_file_before_any_message(tmp_path: Path) -> None:
    """An idle recording still leaves a valid (empty) file."""
    path = tmp_path / "s.mcap"
    with RotatingWriter(path).open():
        assert path.exists()
    assert list(read_records(path)) == []


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        ({"max_bytes": 0}, "rotation size must be positive, got 0 bytes"),
        ({"max_seconds": -1.0}, "rotation duration must be positive, got -1.0 s"),
    ],
)
def test_a_bad_limit_is_refused(policy: dict[str, float], message: str) -> None:
    """Non-positive limits raise InvalidInputError naming the value."""
    with pytest.raises(InvalidInputError, match=message):
        RotationPolicy(**policy)  # type: ignore[arg-type]


def test_many_parts_are_named_by_the_first_and_the_last() -> None:
    """A day rotated every 5 minutes is 288 files: the last line named each."""
    parts = [part_path(Path("s.mcap"), n) for n in range(1, 289)]
    assert parts_named(parts) == "s-0001.mcap ... s-0288.mcap (288 files)"
    assert parts_named(parts[:3]) == "s-0001.mcap, s-0002.mcap, s-0003.mcap"
    assert parts_named([Path("s.mcap")]) == "s.mcap"


def rotate_parts(writer: RotatingWriter, parts: int) -> None:
    """Write until ``parts`` files have been started (2000-byte limit)."""
    i = 0
    while writer.started < parts:
        writer.write("t", "json", SCHEMA, payload(i), i, i)
        i += 1


def test_keep_parts_leaves_the_newest_parts_whole(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """keep_parts=2 over 6 parts: the newest 2 on disk, each with its summary."""
    path = tmp_path / "s.mcap"
    policy = RotationPolicy(max_bytes=2000, keep_parts=2)
    caplog.set_level("INFO", logger="armplan.recording")
    with RotatingWriter(path, policy) as writer:
        rotate_parts(writer, 6)
    assert writer.paths == [part_path(path, 5), part_path(path, 6)]
    assert writer.pruned == [part_path(path, n) for n in range(1, 5)]
    assert sorted(tmp_path.iterdir()) == writer.paths
    for p in writer.paths:
        assert has_summary(p), p
    removed = [
        r.getMessage() for r in caplog.records if "removed old part" in r.message
    ]
    assert len(removed) == 4
    assert str(part_path(path, 1)) in removed[0] and "bytes" in removed[0]


def test_keep_parts_removes_only_files_it_wrote(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A stranger's file at a part's path, a link, a held part: all left, warned."""
    path = tmp_path / "s.mcap"
    stranger = part_path(path, 9)  # named like a part, not this run's
    target = tmp_path / "target.mcap"
    target.write_bytes(b"keep me")
    policy = RotationPolicy(max_bytes=2000, keep_parts=2)
    with RotatingWriter(path, policy) as writer:
        writer.open()
        stranger.write_bytes(b"earlier run")
        rotate_parts(writer, 3)  # part 1 removed as 3 starts
        part_path(path, 2).unlink()  # replaced by another file
        part_path(path, 2).write_bytes(b"someone else's")
        rotate_parts(writer, 4)
        part_path(path, 3).unlink()  # replaced by a link
        part_path(path, 3).symlink_to(target)
        rotate_parts(writer, 5)
        with part_path(path, 4).open("rb") as held:  # another recorder's lock
            fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
            rotate_parts(writer, 6)
        part_path(path, 5).unlink()  # gone already
        rotate_parts(writer, 8)
    assert writer.pruned == [part_path(path, 1), part_path(path, 6)]
    assert writer.paths == [part_path(path, 7), part_path(path, 8)]
    assert stranger.read_bytes() == b"earlier run"
    assert part_path(path, 2).read_bytes() == b"someone else's"
    assert part_path(path, 3).is_symlink() and target.read_bytes() == b"keep me"
    for n in (4, 7, 8):
        assert has_summary(part_path(path, n)), n
    left = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert len(left) == 4
    for n, why in (
        (2, "no longer the file"),
        (3, "Too many levels of symbolic links"),
        (4, "another recorder holds it"),
        (5, "No such file"),
    ):
        assert any(str(part_path(path, n)) in m and why in m for m in left), (n, left)


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        ({"max_bytes": 2000, "keep_parts": 0}, "--keep-parts must be a whole number"),
        ({"max_bytes": 2000, "keep_parts": 1.5}, "--keep-parts must be a whole number"),
        ({"keep_parts": 2}, "--keep-parts needs --rotate-size or --rotate-duration"),
    ],
)
def test_a_bad_keep_parts_is_refused(policy: dict[str, float], message: str) -> None:
    """Below 1, not whole, or without rotation: InvalidInputError on keep_parts."""
    with pytest.raises(InvalidInputError, match=message) as error:
        RotationPolicy(**policy)  # type: ignore[arg-type]
    assert error.value.field == "keep_parts"


def test_parts_past_9999_are_still_the_recordings(tmp_path: Path) -> None:
    """s-10000.mcap on is a part: refused, held against --overwrite, in order.

    --keep-parts lets a recorder run for weeks (10M parts at 740 MB an hour
    pass 9999 in under 6 days); a new recorder at that path saw no part of
    it and wrote beside the live one.
    """
    path = tmp_path / "s.mcap"
    late = [part_path(path, n) for n in (9999, 10000, 10001)]
    assert late[1].name == "s-10000.mcap"
    for p in late[1:]:
        p.write_bytes(b"a live run")
    others = ["s-10000x.mcap", "s-20261127.mcap", "s-01234.mcap"]
    for name in others:  # no part's names: a date, a leading zero
        (tmp_path / name).write_bytes(b"not a part")
    assert numbered_parts(path) == late[1:]
    with pytest.raises(RecordingError, match=r"s-10000\.mcap and 1 more numbered"):
        RotatingWriter(path, RotationPolicy(max_bytes=2000)).open()
    with late[2].open("rb") as held:  # the live recorder's part
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(RecordingError, match="being written by another"):
            RotatingWriter(path, RotationPolicy(max_bytes=2000), overwrite=True).open()
    assert [p.read_bytes() for p in late[1:]] == [b"a live run"] * 2
    assert not part_path(path, 1).exists()
    late[0].write_bytes(b"a live run")
    assert numbered_parts(path) == late  # by number, not by name
    with RotatingWriter(path, RotationPolicy(max_bytes=2000), overwrite=True):
        pass
    for name in others:
        assert (tmp_path / name).read_bytes() == b"not a part", name


def test_keep_parts_leaves_a_new_file_that_took_a_removed_parts_inode(
    tmp_path: Path,
) -> None:
    """A part deleted by someone, a file put at its name: left, inode reused or not.

    ext4 gives a freed inode to the next file made: device and inode alone
    took such a file (a user's restored copy) for the part and removed it.
    """
    path = tmp_path / "s.mcap"
    policy = RotationPolicy(max_bytes=2000, keep_parts=2)
    with RotatingWriter(path, policy) as writer:
        rotate_parts(writer, 3)
        second = part_path(path, 2)
        inode = second.stat().st_ino
        second.unlink()  # deleted by someone else
        for n in range(200):  # a new file, on the same inode if it comes back
            (spare := tmp_path / f"spare-{n}").write_bytes(b"a user's copy")
            if spare.stat().st_ino == inode:
                break
        spare.rename(second)
        rotate_parts(writer, 4)
    assert second.read_bytes() == b"a user's copy"
    assert writer.paths == [part_path(path, 3), part_path(path, 4)]


def test_a_recording_whose_first_part_was_removed_is_still_held(
    tmp_path: Path,
) -> None:
    """keep_parts=1: part 1 gone, the hold moved on; --overwrite still refused."""
    path = tmp_path / "s.mcap"
    with RotatingWriter(path, RotationPolicy(max_bytes=2000, keep_parts=1)) as writer:
        for parts in (2, 3):
            rotate_parts(writer, parts)
            assert numbered_parts(path) == [part_path(path, parts)]
            other = RotatingWriter(path, RotationPolicy(max_bytes=2000), overwrite=True)
            with pytest.raises(RecordingError, match="being written by another"):
                other.open()
            assert part_path(path, parts).exists()
    assert has_summary(part_path(path, 3))
