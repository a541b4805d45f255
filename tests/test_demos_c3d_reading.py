"""ezc3d in a child process: a file that crashes it or makes it allocate
without bound is a DemoFileError naming the file, and the import goes on
being the one to say so."""

from __future__ import annotations

import json
import os
import pathlib
import resource
import select
import signal
import struct
import subprocess
import sys
import threading
import time
from typing import Any

import ezc3d
import numpy as np
import pytest

from shared.demos import c3d_reading
from shared.demos.c3d_import import read_c3d
from shared.demos.c3d_reading import CHILD, read_c3d_file
from shared.demos.markers import MarkerMap
from shared.errors import DemoFileError
from tests.test_demos_c3d import MAP, MAP_NAMES, _write_points, write_reach_c3d

#: Where the reach's file (``write_reach_c3d``) holds these parameters' values.
VALUES = {
    ("ANALOG", "USED"): 692,
    ("ANALOG", "RATE"): 802,
    ("ROTATION", "USED"): 979,
    ("ROTATION", "RATIO"): 1063,
}


@pytest.fixture(scope="module")
def reach(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """A valid C3D file of a reach, 8 kB, written by ezc3d."""
    path = tmp_path_factory.mktemp("reach") / "reach.c3d"
    write_reach_c3d(path)
    return path


def _with(reach: pathlib.Path, path: pathlib.Path, **values: float) -> pathlib.Path:
    """A copy of ``reach`` with parameters set: ``ANALOG_USED=1``, ..."""
    whole = bytearray(reach.read_bytes())
    for key, value in values.items():
        group, name = key.split("_", 1)
        at = VALUES[group, name]
        assert whole[at - 4 - len(name) : at - 4] == name.encode()  # its record
        struct.pack_into("<f" if name == "RATE" else "<h", whole, at, value)
    path.write_bytes(whole)
    return path


def test_a_file_that_makes_ezc3d_segfault_is_named(
    tmp_path: pathlib.Path, reach: pathlib.Path
) -> None:
    """One analog channel at the point rate, and none of its labels, scale
    or offset: ezc3d 1.7.2 segfaults. The importing process lives on."""
    path = _with(reach, tmp_path / "analog.c3d", ANALOG_USED=1, ANALOG_RATE=100.0)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MarkerMap.model_validate(MAP))
    assert caught.value.message == (
        f"{path}: not a readable C3D file: the C3D reader (ezc3d) crashed on it "
        "(SIGSEGV), it is corrupt"
    )


def test_a_file_that_makes_ezc3d_abort_is_named_with_its_words(
    tmp_path: pathlib.Path, reach: pathlib.Path
) -> None:
    """Two rotations, 3 per frame: ezc3d aborts on an uncaught exception;
    the error quotes what it wrote to stderr."""
    path = _with(reach, tmp_path / "turn.c3d", ROTATION_USED=2, ROTATION_RATIO=3)
    with pytest.raises(DemoFileError) as caught:
        read_c3d_file(path)
    assert caught.value.message.startswith(
        f"{path}: not a readable C3D file: the C3D reader (ezc3d) crashed on it "
        "(SIGABRT), it is corrupt; it said: terminate called after throwing an "
        "instance of 'std::out_of_range'"
    )


def test_a_file_that_makes_ezc3d_allocate_without_bound_is_stopped(
    tmp_path: pathlib.Path, reach: pathlib.Path
) -> None:
    """ROTATION:RATIO -20736 per frame: ezc3d grew past 6 GB over 27 s before
    giving up (12.6 GB for another such file). The child may take 0.5 GiB."""
    path = _with(reach, tmp_path / "ratio.c3d", ROTATION_RATIO=-20736)
    with pytest.raises(DemoFileError) as caught:
        read_c3d_file(path)
    assert caught.value.message == (
        f"{path}: not a readable C3D file: reading it needs over 0.5 GiB, far "
        "more than its 8192 bytes hold: its sizes are corrupt"
    )


def test_a_batch_names_the_file_that_crashes_ezc3d(
    tmp_path: pathlib.Path, reach: pathlib.Path
) -> None:
    """`armplan demos import` of a good file and a crashing one used to die
    of the segfault (exit 139) without naming either; it exits 1 naming the
    crashing file."""
    crash = _with(reach, tmp_path / "crash.c3d", ANALOG_USED=1, ANALOG_RATE=100.0)
    markers = tmp_path / "map.json"
    markers.write_text(json.dumps(MAP))
    run = subprocess.run(
        [
            *(sys.executable, "-m", "armplan", "demos", "import", str(reach)),
            *(str(crash), "--markers", str(markers), "-o", str(tmp_path / "o.mcap")),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 1, run
    assert f"{crash}: not a readable C3D file: the C3D reader (ezc3d) crashed" in (
        run.stderr
    )


def test_a_good_file_reads_as_ezc3d_reads_it(reach: pathlib.Path) -> None:
    """The child's answer: the points (3, points, frames), the POINT labels,
    the header's rate, as ezc3d gives them in the importing process."""
    direct = ezc3d.c3d(str(reach))
    read = read_c3d_file(reach)
    np.testing.assert_array_equal(read["data"]["points"], direct["data"]["points"][:3])
    assert read["parameters"]["POINT"]["LABELS"]["value"] == list(MAP_NAMES)
    assert read["header"]["points"]["frame_rate"] == 100.0


def _children(pid: int) -> list[int]:
    """The PIDs of ``pid``'s children (Linux's /proc).

    A thread that ends between the listing and the read is skipped.
    """
    found: list[int] = []
    for task in pathlib.Path(f"/proc/{pid}/task").iterdir():
        try:
            found += [int(c) for c in (task / "children").read_text().split()]
        except FileNotFoundError:  # that thread ended
            continue
    return found


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie, reaped by no one yet, does not)."""
    try:
        status = pathlib.Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return False
    return "\nState:\tZ" not in status


def test_the_reader_ends_with_an_importer_killed_alone(tmp_path: pathlib.Path) -> None:
    """``kill PID`` of the importer alone left ezc3d's child reading, with no
    time limit (the parent kept it). Here the child waits on a FIFO no one
    writes; the importer is SIGKILLed; the child ends with it."""
    fifo = tmp_path / "never.c3d"
    os.mkfifo(fifo)
    code = (
        "import pathlib, sys; from shared.demos.c3d_reading import read_c3d_file; "
        "print('reading', flush=True); read_c3d_file(pathlib.Path(sys.argv[1]))"
    )
    importer = subprocess.Popen(
        [sys.executable, "-c", code, str(fifo)], stdout=subprocess.PIPE, text=True
    )
    children: list[int] = []
    try:
        assert importer.stdout is not None
        assert importer.stdout.readline() == "reading\n"
        deadline = time.monotonic() + 30
        while not (children := _children(importer.pid)):
            assert time.monotonic() < deadline, "no reader was forked"
            time.sleep(0.05)
        importer.kill()
        importer.wait(timeout=30)
        deadline = time.monotonic() + 10
        while _alive(children[0]) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not _alive(children[0]), "the reader outlived its importer"
    finally:
        importer.kill()
        for child in children:  # an orphan of the old code, whoever adopted it
            if _alive(child):
                os.kill(child, signal.SIGKILL)


def _command_line(pid: int, deadline: float) -> bytes:
    """``pid``'s command line once it has become the reader (its ``exec``
    done: read in the middle of it, the command line is empty), or as it
    is at ``deadline`` [s, monotonic]."""
    while True:
        command = pathlib.Path(f"/proc/{pid}/cmdline").read_bytes()
        if str(CHILD).encode() in command or time.monotonic() >= deadline:
            return command
        time.sleep(0.01)


def _signalled_reader(
    fifo: pathlib.Path, signum: signal.Signals
) -> tuple[list[str], str]:
    """The command line of the reader of ``fifo`` (waiting on it, while this
    process runs another thread), and the importer's error once ``signum``
    ended that reader."""
    os.mkfifo(fifo)
    failed: list[DemoFileError] = []

    def read() -> None:
        with pytest.raises(DemoFileError) as caught:
            read_c3d_file(fifo)
        failed.append(caught.value)

    before = set(_children(os.getpid()))  # a fixture's, say
    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    deadline = time.monotonic() + 30
    while not (children := sorted(set(_children(os.getpid())) - before)):
        assert time.monotonic() < deadline, "no reader started"
        time.sleep(0.05)
    try:
        command = _command_line(children[0], deadline)
    finally:
        os.kill(children[0], signum)
        reader.join(timeout=30)
    assert not reader.is_alive()
    (error,) = failed
    return [word.decode() for word in command.split(b"\0") if word], error.message


def test_the_reader_is_a_new_program_not_a_copy_of_the_importer(
    tmp_path: pathlib.Path,
) -> None:
    """A fork copies the locks the importer's other threads hold (this test
    runner's, Zenoh's, libqi's) with no one left to free them: a forked
    reader of a pytest-xdist worker answered nothing for 60 s. The reader
    runs ``c3d_child.py`` in a new interpreter, here caught waiting on a
    FIFO while this process runs another thread, then killed: named."""
    fifo = tmp_path / "never.c3d"
    words, message = _signalled_reader(fifo, signal.SIGKILL)
    assert words[:4] == [sys.executable, "-I", str(CHILD), str(fifo)], words
    assert message == (
        f"{fifo}: not a readable C3D file: the C3D reader (ezc3d) crashed on it "
        "(SIGKILL), it is corrupt"
    )


def test_a_reader_past_its_cpu_time_is_not_said_to_crash(
    tmp_path: pathlib.Path,
) -> None:
    """SIGXCPU (the reader's CPU time limit) was "crashed on it (SIGXCPU),
    it is corrupt"; it is the time the file took."""
    fifo = tmp_path / "slow.c3d"
    _, message = _signalled_reader(fifo, signal.SIGXCPU)
    assert message == (
        f"{fifo}: not a readable C3D file: reading it took over 60 s of CPU time"
    )


def _read_under_cpu_limit(path: pathlib.Path, seconds: int) -> str:
    """What an importer whose shell said ``ulimit -t seconds`` prints."""
    code = (
        "import pathlib, sys; from shared.demos.c3d_reading import read_c3d_file\n"
        "from shared.errors import DemoFileError\n"
        "try:\n"
        "    data = read_c3d_file(pathlib.Path(sys.argv[1]))\n"
        "    print('read', data['data']['points'].shape)\n"
        "except DemoFileError as exc:\n"
        "    print(exc.message)\n"
    )

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds))

    done = subprocess.run(
        [sys.executable, "-c", code, str(path)],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=limit,
        check=True,
    )
    return done.stdout.strip()


def test_a_cpu_time_limit_of_the_shell_is_kept_not_raised(
    reach: pathlib.Path,
) -> None:
    """Under ``ulimit -t 50`` (a shared lab machine's, a batch job's) the
    reader asked for 61 s of CPU, above the hard limit, and failed before
    reading: every good file was "not a readable C3D file: the C3D reader
    (ezc3d) ended without an answer (exit 0)". It keeps the lower limit."""
    frames = ezc3d.c3d(str(reach))["data"]["points"].shape[2]
    assert _read_under_cpu_limit(reach, 50) == f"read (3, {len(MAP_NAMES)}, {frames})"


@pytest.mark.parametrize(("shell", "said"), [(5, "(5, True)"), (None, "(60, False)")])
def test_a_cpu_limit_the_shell_set_is_the_one_blamed(
    shell: int | None, said: str
) -> None:
    """Under ``ulimit -t 5`` a reader past its CPU time hit the shell's limit
    (the error says so: "the 5 s of CPU time this shell allows"), not its
    own 60 s (the file's: "reading it took over 60 s of CPU time")."""
    code = "from shared.demos.c3d_child import cpu_limit; print(cpu_limit(60.0))"

    def limit() -> None:
        if shell is not None:
            resource.setrlimit(resource.RLIMIT_CPU, (shell, shell))

    done = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=limit,
        check=True,
    )
    assert done.stdout.strip() == said


def test_a_reader_the_kernel_killed_at_its_cpu_limit_is_not_said_to_crash(
    tmp_path: pathlib.Path,
) -> None:
    """A limit's soft and hard values are one (``ulimit -t 2`` sets both, as
    the reader does its own), so at it Linux sends SIGKILL, not SIGXCPU: a
    good 96 MB file the reader had no time for read "crashed on it
    (SIGKILL), it is corrupt". Its CPU time says it ran out of it.

    The importer itself lives under the limit too, and its imports take
    about 1 s of CPU here: at ``ulimit -t 1`` it was killed itself once, on
    a loaded machine. The reader takes about 3.2 s for this file."""
    path = tmp_path / "long.c3d"
    labels = [f"M{i}" for i in range(60)]
    _write_points(path, labels, [np.zeros((100_000, 3))] * len(labels))
    assert _read_under_cpu_limit(path, 2) == (
        f"{path}: cannot be read: the C3D reader took over the 2 s of CPU "
        "time this shell allows (ulimit -t)"
    )


def test_the_readers_own_failure_is_said_not_silent(tmp_path: pathlib.Path) -> None:
    """A failure of the reader itself (here its arguments; before, setting
    its CPU limit) ended it with status 0 and no word, and the importer
    blamed the file. It says what failed, with status 1."""
    done = subprocess.run(
        [sys.executable, "-I", str(CHILD), str(tmp_path / "a.c3d")],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1
    assert done.stderr.startswith("ValueError: not enough values to unpack"), done


def test_an_answer_cut_short_by_a_killed_reader_is_named_not_unpickled(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A reader killed while it wrote a large answer (here as the first
    64 kB reach the importer) left part of one: unpickled, that was a
    traceback (``UnpicklingError``). Now it is the reader's crash, named."""
    path = tmp_path / "long.c3d"
    frames = np.linspace(0.0, 1000.0, 20_000)[:, None] * np.ones(3)
    _write_points(path, list(MAP_NAMES), [frames] * len(MAP_NAMES))  # 1.9 MB
    started: list[subprocess.Popen[bytes]] = []
    start, receive = c3d_reading._start, c3d_reading._receive

    def start_and_keep(*args: Any) -> subprocess.Popen[bytes]:
        started.append(start(*args))
        return started[-1]

    def receive_then_kill(reading: int, seconds: float) -> bytes | None:
        assert select.select([reading], [], [], 60.0)[0]
        first = os.read(reading, 1 << 16)
        started[0].kill()
        rest = receive(reading, seconds)
        return None if rest is None else first + rest

    monkeypatch.setattr(c3d_reading, "_start", start_and_keep)
    monkeypatch.setattr(c3d_reading, "_receive", receive_then_kill)
    with pytest.raises(DemoFileError) as caught:
        read_c3d_file(path)
    assert caught.value.message == (
        f"{path}: not a readable C3D file: the C3D reader (ezc3d) crashed on it "
        "(SIGKILL), it is corrupt"
    )
