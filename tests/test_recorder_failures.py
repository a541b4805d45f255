"""The recorder when things go wrong: a full disk, an existing file, odd samples.

A file the file system stops taking (RLIMIT_FSIZE, /dev/full) ends the
recording at once with a one-line error and exit code 1, the messages
that reached the file readable with --recover; an existing recording is
refused unless --overwrite; a sample whose Foxglove poses cannot be made
loses only its poses; NaN is not JSON; a flipped byte is a checksum error.
"""

from __future__ import annotations

import inspect
import json
import logging
import os
import resource
import signal
import stat
import subprocess
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from record_cli import record_command, start_recording

from armplan.launch import free_endpoint
from services.recorder import RecorderProcess, control, sink
from services.recorder.options import RecorderOptions
from services.recorder.routing import Incoming, route
from services.recorder.service import Recorder
from services.recorder.sink import RecordingSink
from shared.bus import Bus, BusConfig, open_router
from shared.errors import InvalidInputError, RecordingError
from shared.messages import JointState, Trajectory
from shared.recording import read_records
from shared.recording.reader import CHANGED, Recording
from shared.recording.rotation import RotatingWriter, RotationPolicy, part_path
from shared.recording.writer import MAX_TIME, MessageWriter
from shared.robot import Side

NS = "recfail"
JOINTS = list(Side.RIGHT.joint_names)
#: A file size the recorder passes after a few dozen 2 kB messages [bytes].
FILE_LIMIT = 64 * 1024


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NS)
    with open_router(config):
        yield config


def record(
    config: BusConfig, out: Path, *extra: str, limit: int | None = None
) -> subprocess.Popen[str]:
    """``armplan record -o out`` on ``config``'s router, files capped at ``limit``."""

    def cap() -> None:
        if limit is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.Popen(
        record_command(config, out, *extra),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "ARMPLAN_ZENOH_CONFIG": ""},
        preexec_fn=cap,
    )


def trajectory(times: list[float]) -> Trajectory:
    n = len(times)
    zeros = [[0.0] * 5 for _ in range(n)]
    return Trajectory(
        arm=Side.RIGHT,
        joint_names=JOINTS,
        times=times,
        positions=[[0.0, -0.1, 0.3, 0.4, 0.0]] * n,
        velocities=zeros,
        accelerations=zeros,
        primitives=["S_R E_PR W_PR"] * n,
        wrist_path=[[0.1, -0.1, 0.0]] * n,
    )


def test_a_full_file_stops_the_recorder_at_once_with_the_reason(
    config: BusConfig, tmp_path: Path
) -> None:
    """Files capped at 64 kB: the recorder exits 1 within seconds of the cap,
    naming the file and the reason, no traceback; what reached the file
    reads back with recover, and it is what the recorder counted or fewer."""
    out = tmp_path / "full.mcap"
    process = record(config, out, limit=FILE_LIMIT)
    try:
        assert process.stdout is not None
        assert "armplan record: recording" in process.stdout.readline()
        _publish_until_exit(config, process)
        _, stderr = process.communicate(timeout=30)
    finally:
        process.kill()
        process.wait(30)
    print("\n" + stderr)
    assert process.returncode == 1
    assert "Traceback" not in stderr
    line = stderr.strip().splitlines()[-1]
    assert line.startswith(f"armplan: error: cannot write {out}: File too large;")
    assert line.endswith(
        f"armplan inspect --recover {out} reads them (the file lacks its summary)"
    )
    said = int(line.split("recording stopped after ")[1].split(" messages")[0])
    kept = [r for r in read_records(out, recover=True) if r.topic.endswith("misc/x")]
    assert 10 <= len(kept) <= said
    assert os.path.getsize(out) <= FILE_LIMIT


@pytest.mark.parametrize("keep", [None, 2], ids=["all-kept", "keep-parts-2"])
def test_a_full_part_of_a_rotating_recording_names_where_the_messages_are(
    config: BusConfig, tmp_path: Path, keep: int | None
) -> None:
    """Rotating at 16 kB, files capped at 64 kB: a 100 kB message fails in a
    later part. The error said "--recover r-0004.mcap reads them" of every
    message of the recording, most of them in the earlier parts (whole);
    it now says how many parts there are and that only the last one lacks
    its summary. With --keep-parts it said "the earlier parts are whole"
    of parts it had removed; it now says they were removed, and which are
    whole."""
    out = tmp_path / "r.mcap"
    extra = [] if keep is None else ["--keep-parts", str(keep)]
    process = record(config, out, "--rotate-size", "16k", *extra, limit=FILE_LIMIT)
    try:
        assert process.stdout is not None
        assert "armplan record: recording" in process.stdout.readline()
        small = json.dumps({"pad": "x" * 2000}).encode()
        with Bus.connect(config) as bus:
            deadline = time.monotonic() + 30.0
            while not part_path(out, 3).exists():  # two whole parts
                assert time.monotonic() < deadline, "no third part"
                bus.session.put(bus.key("misc/x"), small)
                time.sleep(0.005)
            bus.session.put(bus.key("misc/x"), json.dumps({"pad": "x" * 10**5}))
        _, stderr = process.communicate(timeout=30)
    finally:
        process.kill()
        process.wait(30)
    print("\n" + stderr)
    assert process.returncode == 1
    last = sorted(tmp_path.glob("r-*.mcap"))[-1]
    number = int(last.stem.split("-")[1])
    assert number >= 3
    line = stderr.strip().splitlines()[-1]
    assert line.startswith(f"armplan: error: cannot write {last}: File too large;")
    earlier = (
        "the earlier parts are whole"
        if keep is None
        else f"the {'oldest part' if number == 3 else f'{number - 2} oldest parts'} "
        f"removed (--keep-parts {keep}), {part_path(out, number - 1)} is whole"
    )
    assert line.endswith(
        f"messages in {number} parts: {earlier}, and armplan inspect --recover "
        f"{last} reads what it holds (it lacks its summary)"
    )
    first = 1 if keep is None else number - keep + 1
    assert sorted(tmp_path.glob("r-*.mcap")) == [
        part_path(out, n) for n in range(first, number + 1)
    ]
    for whole in range(first, number):
        assert list(read_records(part_path(out, whole)))  # whole: no error
    with pytest.raises(RecordingError, match="damaged after"):
        list(read_records(last))


def test_a_recorder_process_that_failed_makes_stop_raise(
    config: BusConfig, tmp_path: Path
) -> None:
    """RecorderProcess (what `armplan demo` records with): its file capped
    while it runs, the recorder exits 1 at once; stop() raises with its
    reason and its log. It returned the file as if whole."""
    out, log = tmp_path / "capped.mcap", tmp_path / "recorder.log"
    with log.open("w") as stream:
        recorder = RecorderProcess.start(config, out, keys=["misc/*"], log=stream)
    try:
        resource.prlimit(recorder.pid, resource.RLIMIT_FSIZE, (FILE_LIMIT,) * 2)
        _publish_until_exit(config, recorder.process)
        assert recorder.process.returncode == 1
        with pytest.raises(RecordingError) as caught:
            recorder.stop()
    finally:
        recorder.kill()
    message = caught.value.message
    print("\n" + message)
    assert message.startswith(
        f"the recorder of {out} failed (exit code 1): cannot write {out}: File "
        "too large; recording stopped after "
    )
    assert message.endswith(
        f"armplan inspect --recover {out} reads them (the file lacks its "
        f"summary); see its log {log}"
    )
    assert caught.value.path == str(out)
    with pytest.raises(RecordingError, match="damaged after"):
        list(read_records(out))


@pytest.mark.parametrize("rotates", [False, True], ids=["one-file", "rotating"])
def test_a_recorder_process_killed_by_someone_else_makes_stop_raise(
    config: BusConfig, tmp_path: Path, rotates: bool
) -> None:
    """SIGKILL from outside (the OOM killer): stop() names the signal and
    the file left without its summary: with rotation the part it was
    writing (killed-0001.mcap; it said "killed.mcap", which does not exist)."""
    out = tmp_path / "killed.mcap"
    rotation = RotationPolicy(max_seconds=3600.0) if rotates else RotationPolicy()
    recorder = RecorderProcess.start(
        config,
        out,
        keys=["misc/*"],
        options=RecorderOptions(rotation=rotation),
        log=subprocess.DEVNULL,
    )
    try:
        os.kill(recorder.pid, signal.SIGKILL)
        recorder.process.wait(30)
        with pytest.raises(RecordingError) as caught:
            recorder.stop()
    finally:
        recorder.kill()
    left = part_path(out, 1) if rotates else out
    assert left.exists()
    assert caught.value.message == (
        f"the recorder of {out} was killed by SIGKILL; {left} lacks its summary; "
        "see its log"
    )


def test_a_recorder_process_gets_its_own_time_to_write_out() -> None:
    """RecorderProcess waits longer than the recorder's own bound for
    writing out its queue (it killed it after 15 s, the bound being 30)."""
    assert control.STOP_TIMEOUT >= sink.STOP_TIMEOUT + 10.0
    assert inspect.signature(RecorderProcess.stop).parameters["timeout"].default == (
        control.STOP_TIMEOUT
    )


def _publish_until_exit(config: BusConfig, process: subprocess.Popen[str]) -> None:
    """Publish 2 kB messages on misc/x until ``process`` exits (30 s at most)."""
    payload = json.dumps({"pad": "x" * 2000}).encode()
    with Bus.connect(config) as bus:
        publisher = bus.session.declare_publisher(
            bus.key("misc/x"), congestion_control=zenoh.CongestionControl.BLOCK
        )
        deadline = time.monotonic() + 30.0
        while process.poll() is None:
            assert time.monotonic() < deadline, "still recording past the cap"
            publisher.put(payload)
            time.sleep(0.005)
        publisher.undeclare()


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_device_that_takes_nothing_is_one_line(
    config: BusConfig, tmp_path: Path
) -> None:
    """-o /dev/full: refused as existing; with --overwrite, cannot write."""
    for extra, said in (
        ((), "armplan: error: /dev/full exists: give another name, or --overwrite"),
        (("--overwrite",), "armplan: error: cannot write /dev/full: No space left"),
    ):
        process = record(config, Path("/dev/full"), "--duration", "2", *extra)
        _, stderr = process.communicate(timeout=60)
        assert process.returncode == 1, stderr
        assert stderr.startswith(said), stderr
        assert "Traceback" not in stderr


@pytest.mark.parametrize("reader", [False, True])
def test_a_named_pipe_is_refused_not_waited_on(
    config: BusConfig, tmp_path: Path, reader: bool
) -> None:
    """-o FIFO --overwrite: one line naming it, exit 1, whether it is read.

    Without a reader it used to wait in open() for ever, deaf to Ctrl-C and
    SIGTERM (their handler only sets the stop flag): only SIGKILL ended it.
    With one it failed "cannot write ...: Illegal seek" (or hung as well).
    """
    fifo = tmp_path / "pipe.mcap"
    os.mkfifo(fifo)
    held = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK) if reader else None
    process = record(config, fifo, "--duration", "1", "--overwrite")
    try:
        _, stderr = process.communicate(timeout=60)
    finally:
        process.kill()
        if held is not None:
            os.close(held)
    assert process.returncode == 1, stderr
    assert stderr == (
        f"armplan: error: {fifo} is a named pipe, not a file: a recording is "
        "written to a file (its writer needs to know its position in it); "
        "give a file's name\n"
    )
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)  # left as it was


def test_an_existing_recording_is_refused_unless_overwrite(tmp_path: Path) -> None:
    """The file is left as it was; --overwrite (overwrite=True) replaces it."""
    out = tmp_path / "taken.mcap"
    out.write_bytes(b"an earlier session")
    with pytest.raises(RecordingError, match=r"taken\.mcap exists: give another"):
        RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    assert out.read_bytes() == b"an earlier session"
    options = RecorderOptions(output=out, keys=("**",), overwrite=True)
    RecordingSink(options, NS).start().stop()
    assert [r.topic for r in read_records(out)] == ["/robot_description"]


def test_two_writers_cannot_share_a_file(tmp_path: Path) -> None:
    """Created exclusively: the second writer of one path is refused, told
    the first is writing it (not sent to --overwrite, refused as well)."""
    out = tmp_path / "one.mcap"
    with (
        MessageWriter(out, chunked=False, overwrite=False),
        pytest.raises(RecordingError, match="is being written by another recorder"),
    ):
        MessageWriter(out, chunked=False, overwrite=False)


def test_earlier_numbered_files_are_refused_or_all_replaced(tmp_path: Path) -> None:
    """Rotation: parts of an earlier recording are refused; with overwrite
    every one goes, so no stale part is left beside the new ones."""
    path = tmp_path / "r.mcap"
    for n in (1, 2, 3):
        part_path(path, n).write_bytes(b"old")
    policy = RotationPolicy(max_bytes=10_000)
    with pytest.raises(
        RecordingError, match=r"r-0001\.mcap and 2 more numbered files of an earlier"
    ):
        RotatingWriter(path, policy, overwrite=False).open()
    with RotatingWriter(path, policy, overwrite=True).open():
        pass
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r-0001.mcap"]


def test_a_folder_is_refused_as_a_folder(tmp_path: Path) -> None:
    """A folder at the path is named as one, with or without overwrite and
    rotation: it used to be "exists: ..., or --overwrite", and --overwrite
    then failed "Is a directory" (with rotation, parts went beside it)."""
    folder = tmp_path / "sessions"
    folder.mkdir()
    said = f"{folder} is a folder: name the recording's file, e.g. {folder}/session"
    cases = [
        lambda: MessageWriter(folder, chunked=False, overwrite=False),
        lambda: MessageWriter(folder, chunked=False, overwrite=True),
        lambda: RotatingWriter(folder, RotationPolicy(max_bytes=10_000)).open(),
        lambda: RotatingWriter(
            folder, RotationPolicy(max_bytes=10_000), overwrite=True
        ).open(),
    ]
    for make in cases:
        with pytest.raises(RecordingError) as caught:
            make()
        assert caught.value.message.startswith(said)
        assert "overwrite" not in caught.value.message
    assert folder.is_dir() and list(folder.iterdir()) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sessions"]


@pytest.mark.parametrize("extra", [(), ("--overwrite",), ("--rotate-size", "1M")])
def test_record_into_a_folder_is_refused_as_a_folder(
    config: BusConfig, tmp_path: Path, extra: tuple[str, ...]
) -> None:
    """`armplan record -o DIR`: exit 1, one line naming the folder, no hint
    to --overwrite (which used to fail "Is a directory")."""
    process = record(config, tmp_path, "--duration", "2", *extra)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 1, stderr
    assert stderr == (
        f"armplan: error: {tmp_path} is a folder: name the recording's file, "
        f"e.g. {tmp_path}/session.mcap\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_record_into_a_missing_folder_is_refused_not_made_a_file(
    config: BusConfig, tmp_path: Path
) -> None:
    """`armplan record -o newdir/` with no folder newdir: exit 1, one line;
    it used to record into a file named newdir (the slash dropped)."""
    command = record_command(config, tmp_path / "newdir", "--duration", "1")
    command[command.index("-o") + 1] += "/"
    process = subprocess.run(
        command, capture_output=True, text=True, timeout=60, check=False
    )
    assert process.returncode == 1, process.stderr
    assert process.stderr == (
        f"armplan: error: {tmp_path}/newdir/ ends with /, as a folder's name, "
        f"and there is no folder {tmp_path}/newdir: create it and name the "
        f"recording's file, e.g. {tmp_path}/newdir/session.mcap\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_a_sample_without_poses_loses_only_its_poses(tmp_path: Path) -> None:
    """A trajectory stamped a second before MCAP's clock ends (its poses
    would pass 2^64 ns) is written, its Foxglove poses skipped, and the
    writer goes on; times of 2e10 s, which once did the same, are no
    trajectory any more and go to the json channel, also kept."""
    out = tmp_path / "odd.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    late = MAX_TIME - 10**9
    data = json.loads(trajectory([0.0, 2.0]).to_json())
    far_apart = json.dumps(data | {"times": [0.0, 2e10]}).encode()
    state = JointState(
        joint_names=JOINTS, positions=[0.0, -0.1, 0.3, 0.4, 0.0], time=1.0
    )
    samples = [
        ("plan/trajectory", trajectory([0.0, 2.0]).to_json().encode(), late),
        ("plan/trajectory", far_apart, 1),
        ("bridge/state", state.to_json().encode(), 2),
    ]
    for key, payload, t in samples:
        sink.put(Incoming(f"{NS}/{key}", payload, "application/json", t, t))
    sink.stop()
    assert sink.error is None and sink.failed == 0 and sink.written == 3
    records = list(read_records(out))
    mine = [r for r in records if r.topic.startswith(NS)]
    assert [r.raw for r in mine] == [payload for _, payload, _ in samples]
    assert [r.schema for r in mine] == ["Trajectory", "json", "JointState"]
    assert not any(r.topic.startswith("/tf/planned") for r in records)
    assert any(r.topic.startswith("/tf/executed") for r in records)  # the state's


def test_nan_is_not_json() -> None:
    """Python's NaN and Infinity go to the raw channel, kept byte for byte."""
    for payload in (b'{"time": NaN}', b'{"x": -Infinity}'):
        entry = route(Incoming(f"{NS}/misc/x", payload, "x", 1, 1), NS)
        assert entry.schema_name == "RawPayload"


def test_a_time_beyond_mcap_is_refused_before_a_byte(tmp_path: Path) -> None:
    """log_time 2^64 ns: refused; the file stays whole and readable."""
    out = tmp_path / "t.mcap"
    with MessageWriter(out, chunked=False) as writer:
        channel = writer.add_channel("a", "json", {})
        writer.write_raw(channel, b"{}", MAX_TIME)
        with pytest.raises(InvalidInputError, match="log_time 18446744073709551616"):
            writer.write_raw(channel, b"{}", MAX_TIME + 1)
        writer.write_raw(channel, b"{}", 5)
    assert [r.log_time for r in read_records(out)] == [MAX_TIME, 5]


def test_a_changed_byte_is_a_checksum_error(tmp_path: Path) -> None:
    """A digit changed inside a message keeps it valid JSON; the data
    section's checksum still tells the file was changed."""
    out = tmp_path / "c.mcap"
    with MessageWriter(out, chunked=False) as writer:
        channel = writer.add_channel("a", "json", {})
        for i in range(10):
            writer.write_raw(channel, json.dumps({"t": 0.45 + i}).encode(), i + 1)
    data = out.read_bytes()
    out.write_bytes(data.replace(b'"t": 3.45', b'"t": 3.49', 1))
    recording = Recording(out)
    assert len(list(recording)) == 10
    assert recording.damage == CHANGED
    with pytest.raises(RecordingError) as caught:
        list(read_records(out))
    assert caught.value.message.endswith(
        "its checksum does not match: bytes were changed after it was written, "
        "somewhere in its 10 messages (which cannot be told); --recover (or "
        "recover=True) reads them all, the changed bytes included"
    )


def test_the_recorder_says_when_the_router_goes_and_comes_back(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A router stopped under a recorder: a warning that nothing is recorded
    until it is back, then one when it is; the recording goes on."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NS)
    out = tmp_path / "gone.mcap"

    def said(text: str, timeout: float = 30.0) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            recorder.watch_router()
            if any(text in r.getMessage() for r in caplog.records):
                return True
            time.sleep(0.1)
        return False

    caplog.set_level(logging.WARNING, logger="armplan.recorder")
    router = open_router(config)
    with (
        Bus.connect(config) as bus,
        Recorder(bus, RecorderOptions(output=out, keys=("misc/*",))) as recorder,
    ):
        router.close()
        assert said(f"lost the router at {config.endpoint}; nothing is recorded")
        with open_router(config):
            assert said(f"the router at {config.endpoint} is back; recording")
    assert [r.topic for r in read_records(out)] == ["/robot_description"]  # whole


def test_a_recorder_on_a_peer_records_and_says_nothing_is_lost(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """`--connect` to a peer-mode session listening there: what the peer
    publishes is recorded, and no warning says the router was lost (it
    said so at once: routers_zid lists routers only)."""
    endpoint = free_endpoint()
    peer_config = zenoh.Config()
    peer_config.insert_json5("mode", '"peer"')
    peer_config.insert_json5("listen/endpoints", json.dumps([endpoint]))
    peer_config.insert_json5("scouting/multicast/enabled", "false")
    peer_config.insert_json5("scouting/gossip/enabled", "false")
    caplog.set_level(logging.WARNING, logger="armplan.recorder")
    out = tmp_path / "peer.mcap"
    config = BusConfig(endpoints=(endpoint,), namespace=NS)
    with (
        zenoh.open(peer_config) as peer,
        Bus.connect(config, wait=10.0) as bus,
        Recorder(bus, RecorderOptions(output=out, keys=("misc/*",))) as recorder,
    ):
        deadline = time.monotonic() + 20
        while recorder.sink.written < 4 and time.monotonic() < deadline:
            peer.put(f"{NS}/misc/ping", b'{"n": 1}', encoding="application/json")
            recorder.watch_router()
            time.sleep(0.1)
    topics = [r.topic for r in read_records(out)]
    assert "misc/ping" in [t.rsplit(NS + "/", 1)[-1] for t in topics], topics
    assert not [r for r in caplog.records if "lost the router" in r.getMessage()]


def test_overwrite_finds_the_parts_of_a_name_with_glob_characters(
    tmp_path: Path,
) -> None:
    """`r[1].mcap` rotated: its parts are found (the name is no pattern), so
    --overwrite removes them all and a plain run refuses them."""
    path = tmp_path / "r[1].mcap"
    for n in (1, 2, 3):
        part_path(path, n).write_bytes(b"old")
    policy = RotationPolicy(max_bytes=10_000)
    with pytest.raises(RecordingError, match="and 2 more numbered files"):
        RotatingWriter(path, policy).open()
    with RotatingWriter(path, policy, overwrite=True).open():
        pass
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r[1]-0001.mcap"]


def test_a_stop_with_a_backlog_says_it_is_writing_it_out(
    config: BusConfig, tmp_path: Path
) -> None:
    """Ctrl-C with three 20 000-sample trajectories queued (each makes 40 000
    Foxglove messages): the recorder wrote for seconds with no word, and a
    second Ctrl-C did nothing visible. It now says at once that it writes
    out the queue, and still closes the file whole (exit 0)."""
    out = tmp_path / "backlog.mcap"
    payload = trajectory([i * 0.01 for i in range(20_000)]).to_json().encode()
    process = start_recording(
        [*record_command(config, out), "--keys", "plan/trajectory"]
    )
    try:
        with Bus.connect(config) as bus:
            for _ in range(3):
                bus.session.put(
                    bus.key("plan/trajectory"),
                    payload,
                    congestion_control=zenoh.CongestionControl.BLOCK,
                )
            time.sleep(0.3)  # they reach the recorder; writing one takes ~1 s
        process.send_signal(signal.SIGINT)
        time.sleep(0.2)
        process.send_signal(signal.SIGINT)  # the impatient second Ctrl-C
        stdout, stderr = process.communicate(timeout=60)
    finally:
        process.kill()
        process.wait(30)
    print("\n" + stderr)
    assert process.returncode == 0, stderr
    assert "armplan record: stopping; writing out " in stderr
    assert "messages still queued (at most 30 s), then closing the file whole" in stderr
    assert "armplan record: 3 messages" in stdout
    assert len([r for r in read_records(out) if r.topic.endswith("trajectory")]) == 3


@pytest.mark.parametrize(
    ("extra", "said"),
    [
        (
            ["-o", ""],
            "-o is empty: name the recording's file (or leave -o out for "
            "armplan-DATE-TIME.mcap here)",
        ),
        (["--flush-every", "0"], "--flush-every must be in (0, 10] s, got 0"),
        (["--flush-every", "nan"], "--flush-every must be in (0, 10] s, got nan"),
    ],
    ids=["empty-output", "flush-0", "flush-nan"],
)
def test_a_bad_output_or_flush_is_named_by_its_option(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    extra: list[str],
    said: str,
) -> None:
    """`-o ""` recorded under the default name as if -o were not given;
    `--flush-every 0` was told as the options' field ("flush_every must
    be ..."). Both refused before any router is looked for, naming the option."""
    from armplan.cli.main import main

    monkeypatch.chdir(tmp_path)
    endpoint = free_endpoint()
    assert main(["record", "--connect", endpoint, "--duration", "1", *extra]) == 1
    assert capsys.readouterr().err == f"armplan: error: {said}\n"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("reader", [False, True])
def test_a_pipe_put_there_after_the_check_is_refused_not_waited_on(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, reader: bool
) -> None:
    """The path is checked, then opened: a named pipe put there in between
    (here: the first check passed over) was opened blocking, and the
    recorder waited for a reader for ever. Opened not blocking, it is seen
    and refused."""
    from shared.recording import file_lock

    fifo = tmp_path / "pipe.mcap"
    os.mkfifo(fifo)
    held = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK) if reader else None
    check = file_lock._refuse_pipe
    calls: list[Path] = []

    def late_check(path: Path) -> None:
        calls.append(path)
        if len(calls) > 1:  # the first: still a file then
            check(path)

    monkeypatch.setattr(file_lock, "_refuse_pipe", late_check)
    outcome: list[BaseException | object] = []

    def open_it() -> None:
        try:
            outcome.append(file_lock.open_locked(fifo, overwrite=True))
        except BaseException as exc:
            outcome.append(exc)

    opener = threading.Thread(target=open_it, daemon=True)
    opener.start()
    opener.join(timeout=10)
    try:
        assert not opener.is_alive(), "it waits for a reader"
    finally:
        if opener.is_alive():  # set it free: a reader or a writer comes
            os.close(os.open(fifo, os.O_RDWR))
        if held is not None:
            os.close(held)
    (error,) = outcome
    assert isinstance(error, RecordingError), error
    assert error.message.startswith(f"{fifo} is a named pipe, not a file")
