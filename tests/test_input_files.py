"""Input files read whole up to a size, whatever kind of file they are."""

from __future__ import annotations

import errno
import os
import pathlib
import threading

import pytest

from shared.input_files import read_at_most, without_byte_order_mark


def test_a_file_up_to_the_limit_is_read_and_one_byte_more_refused(
    tmp_path: pathlib.Path,
) -> None:
    file = tmp_path / "data.json"
    file.write_bytes(b"x" * 10)
    assert read_at_most(file, 10) == b"x" * 10
    with pytest.raises(OSError, match="more than 9 bytes") as caught:
        read_at_most(file, 9)
    assert caught.value.errno == errno.EFBIG and caught.value.filename == str(file)


def test_a_device_without_end_is_refused_at_the_limit() -> None:
    """/dev/zero has st_size 0: a check of the size passed it, then reading
    it whole took 15 GB in 20 s."""
    with pytest.raises(OSError, match="more than 1000 bytes"):
        read_at_most("/dev/zero", 1000)


def test_a_pipe_is_read_up_to_the_limit(tmp_path: pathlib.Path) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    writer = threading.Thread(target=feed, args=(fifo, 5000))
    writer.start()
    try:
        with pytest.raises(OSError, match="more than 4096 bytes"):
            read_at_most(fifo, 4096)
    finally:
        writer.join()


def feed(fifo: pathlib.Path, size: int) -> None:
    """Write ``size`` bytes into ``fifo``, up to the reader's leaving."""
    try:
        with open(fifo, "wb") as stream:
            stream.write(b"y" * size)
    except BrokenPipeError:
        pass


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["plan", "--task", "/dev/zero"], "cannot read the task (more than"),
        (["plan", "--wrist-path", "/dev/zero"], "cannot read the wrist path (more"),
        (["decide", "--wrist-path", "/dev/zero"], "cannot read the wrist path (more"),
        (
            ["decide", "--model", "/dev/zero", "--target", "0.12", "-0.1", "0.05"],
            "cannot read it ([Errno 27] more than",
        ),
        (
            ["export", "python", "/dev/zero", "-o", "x.py"],
            "cannot read /dev/zero: more",
        ),
    ],
    ids=["task", "plan-csv", "decide-csv", "model", "export"],
)
def test_a_command_given_a_file_without_end_refuses_it(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Each read its file whole: `armplan plan --task /dev/zero` took 15 GB
    in 20 s, and under `ulimit -v` ended in a MemoryError traceback."""
    from armplan.cli.main import main

    assert main(args) == 1
    error = capsys.readouterr().err
    assert message in error and "Traceback" not in error


def test_a_marker_map_or_demo_task_without_end_is_refused() -> None:
    from armplan.demo.task import load_task
    from shared.demos.markers import read_marker_map
    from shared.errors import DemoFileError, InvalidInputError

    with pytest.raises(DemoFileError, match="cannot read the marker map: more than"):
        read_marker_map("/dev/zero")
    with pytest.raises(InvalidInputError, match="/dev/zero: more than"):
        load_task("/dev/zero")


def test_a_byte_order_mark_is_dropped_and_nothing_else() -> None:
    assert without_byte_order_mark(b"\xef\xbb\xbf{}") == b"{}"
    assert without_byte_order_mark(b"{}") == b"{}"
    assert without_byte_order_mark(b"\xef\xbb{}") == b"\xef\xbb{}"
