"""Replay: a recording's messages sent again, same bytes, same order, same timing.

A session is recorded by the recorder process from a publisher that sends
with known gaps, then ``armplan replay`` (a real process) sends it again
under another namespace to a subscriber in this test.

Timing tolerance: each message must arrive within ``TOLERANCE`` of its
recorded offset divided by the speed, after aligning the two time axes on
their median difference (so one late first message does not shift all the
others). The recorded offsets come from the router's timestamps, taken as
each message entered it. A replay adds its sleep's wake-up latency (~1 ms),
Zenoh's loopback latency (well under 1 ms), and the scheduling of four busy
processes on two CPU cores shared with other test runs. Typically the error
is under 6 ms; the worst seen was 65 ms, with both cores saturated. 100 ms
still fails a speed error of 10 % (130 ms on the last message, 1.3 s in), and
the order is checked exactly.
"""

from __future__ import annotations

import json
import signal
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh

from armplan.launch import free_endpoint
from services.recorder import RecorderProcess
from services.recorder.replay import ReplayItem, replay, replay_items
from shared.bus import Bus, BusConfig, open_router
from shared.bus.keys import alive_key
from shared.errors import InvalidInputError

NAMESPACE = "replaytest"
TARGET = "replayed"
TOLERANCE = 0.1  # [s]
#: Send offsets of the recorded messages [s].
OFFSETS = [0.0, 0.1, 0.25, 0.45, 0.8, 0.9, 1.3]


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


def payloads() -> list[tuple[str, bytes]]:
    keys = ["plan/request", "plan/trajectory", "bridge/state", "misc/raw"]
    out = []
    for i, _ in enumerate(OFFSETS):
        key = keys[i % len(keys)]
        body = b"\x00raw\xff%d" % i if key == "misc/raw" else b'{"i": %d}' % i
        out.append((key, body))
    return out


@pytest.fixture(scope="module")
def recording(
    config: BusConfig, tmp_path_factory: pytest.TempPathFactory
) -> tuple[Path, list[float]]:
    """A recorded session; returns the file and the actual send offsets [s]."""
    out = tmp_path_factory.mktemp("replay") / "session.mcap"
    sent: list[float] = []
    with (
        RecorderProcess.start(config, out, keys=["plan/*", "bridge/*", "misc/*"]),
        Bus.connect(config) as bus,
    ):
        start = time.monotonic()
        for offset, (key, body) in zip(OFFSETS, payloads(), strict=True):
            time.sleep(max(0.0, start + offset - time.monotonic()))
            sent.append(time.monotonic() - start)
            bus.session.put(bus.key(key), body)
        time.sleep(0.3)
    return out, sent


class Listener:
    """Collects (relative key, payload, arrival time [s]) under a namespace."""

    def __init__(self, bus: Bus, namespace: str) -> None:
        self.got: list[tuple[str, bytes, float]] = []
        self.encodings: list[str] = []
        self.prefix = f"{namespace}/"
        self._lock = threading.Lock()
        self._sub = bus.session.declare_subscriber(f"{namespace}/**", self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr).removeprefix(self.prefix)
        with self._lock:
            self.got.append((key, sample.payload.to_bytes(), time.monotonic()))
            self.encodings.append(str(sample.encoding))

    def wait(self, n: int, timeout: float = 20.0) -> None:
        deadline = time.monotonic() + timeout
        while len(self.got) < n and time.monotonic() < deadline:
            time.sleep(0.02)

    def close(self) -> None:
        self._sub.undeclare()


def armplan_replay(config: BusConfig, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "armplan",
            "replay",
            *args,
            "--connect",
            config.endpoint,
            "--namespace",
            TARGET,
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def replay_into_listener(
    config: BusConfig, path: Path, *args: str, expect: int = len(OFFSETS)
) -> tuple[subprocess.CompletedProcess[str], list[tuple[str, bytes, float]]]:
    """Run `armplan replay`; what arrived (waiting up to 5 s for ``expect``)."""
    with Bus.connect(config) as bus:
        listener = Listener(bus, TARGET)
        try:
            out = armplan_replay(config, str(path), *args)
            listener.wait(expect if out.returncode == 0 else 0, timeout=5.0)
        finally:
            listener.close()
    return out, listener.got


@pytest.mark.parametrize("speed", [1.0, 2.0])
def test_replay_sends_the_same_messages_with_their_timing(
    config: BusConfig, recording: tuple[Path, list[float]], speed: float
) -> None:
    """Same keys, bytes and order; arrival offsets = recorded offsets / speed."""
    path, sent = recording
    out, got = replay_into_listener(config, path, "--speed", str(speed))
    assert out.returncode == 0, out.stderr
    assert f"sent {len(OFFSETS)} of {len(OFFSETS)} messages" in out.stdout
    assert [(k, p) for k, p, _ in got] == payloads()
    recorded = [item.offset for item in replay_items(path)]
    lags = [t - r / speed for (_, _, t), r in zip(got, recorded, strict=True)]
    errors = [abs(lag - statistics.median(lags)) for lag in lags]
    print(f"speed {speed:g}: timing errors [ms]", [round(e * 1000, 1) for e in errors])
    assert max(errors) < TOLERANCE
    assert max(abs(r - s) for r, s in zip(recorded, sent, strict=True)) < TOLERANCE


def test_replayed_messages_keep_their_zenoh_encoding(
    config: BusConfig, recording: tuple[Path, list[float]]
) -> None:
    """Published with Zenoh's default encoding, the JSON objects came back as
    application/json; now each comes back with the encoding it was recorded
    with (the raw bytes kept theirs already)."""
    path, _ = recording
    with Bus.connect(config) as bus:
        listener = Listener(bus, TARGET)
        try:
            out = armplan_replay(config, str(path), "--speed", "10")
            listener.wait(len(OFFSETS), timeout=5.0)
        finally:
            listener.close()
    assert out.returncode == 0, out.stderr
    assert listener.encodings == ["zenoh/bytes"] * len(OFFSETS)


def test_replay_of_chosen_keys_only(
    config: BusConfig, recording: tuple[Path, list[float]]
) -> None:
    """--keys bridge/* plan/request sends only those, in recorded order."""
    path, _ = recording
    wanted = [(k, p) for k, p in payloads() if k in ("bridge/state", "plan/request")]
    out, got = replay_into_listener(
        config,
        path,
        *("--keys", "bridge/*", "plan/request", "--speed", "10"),
        expect=len(wanted),
    )
    assert out.returncode == 0, out.stderr
    assert [(k, p) for k, p, _ in got] == wanted


def test_replay_of_a_damaged_file_fails_clearly_or_sends_its_prefix(
    config: BusConfig, recording: tuple[Path, list[float]], tmp_path: Path
) -> None:
    """A truncated copy: exit 1 'armplan: error:'; with --recover, its prefix."""
    path, _ = recording
    cut = tmp_path / "cut.mcap"
    data = path.read_bytes()
    cut.write_bytes(data[: data.index(b'{"i": 4}') + 3])  # inside message 4
    out, got = replay_into_listener(config, cut)
    assert out.returncode == 1
    assert out.stderr.startswith("armplan: error:")
    assert "Traceback" not in out.stderr
    assert got == []
    out, got = replay_into_listener(config, cut, "--recover", "--speed", "10", expect=4)
    assert out.returncode == 0, out.stderr
    assert [(k, p) for k, p, _ in got] == payloads()[:4]


def test_a_message_found_bad_while_sending_ends_the_replay_with_a_count(
    config: BusConfig, tmp_path: Path
) -> None:
    """A raw payload that does not decode (another writer's, checksum right)
    is found when read to be sent: exit 1 naming the file, after saying how
    many messages went out before it."""
    from shared.recording import MessageWriter
    from shared.recording.raw_payload import JSON_SCHEMA, RawPayload

    path = tmp_path / "raw.mcap"
    with MessageWriter(path, chunked=False) as writer:
        ok = writer.add_channel("misc/ok", "json", JSON_SCHEMA)
        writer.write_raw(ok, b'{"i": 0}', 10**18)
        raw = writer.add_channel("misc/raw", RawPayload.__name__, JSON_SCHEMA)
        writer.write_raw(raw, b'{"encoding": "x", "base64": "!"}', 10**18 + 1)
    out, got = replay_into_listener(config, path, expect=1)
    assert out.returncode == 1
    assert (
        "armplan replay: sent 1 of 2 messages, then stopped at a message it "
        "could not read"
    ) in out.stdout
    assert out.stderr.startswith(f"armplan: error: {path}: a raw payload cannot")
    assert [(k, p) for k, p, _ in got] == [("misc/ok", b'{"i": 0}')]


def test_replay_waits_for_a_missing_service_then_fails(
    config: BusConfig, recording: tuple[Path, list[float]]
) -> None:
    """--wait-for bridge with no bridge: a clear error naming it."""
    path, _ = recording
    out = armplan_replay(config, str(path), "--wait-for", "bridge", "--wait", "0.5")
    assert out.returncode == 1
    assert "service 'bridge' is unavailable" in out.stderr


def test_a_whole_recording_is_not_replayed_into_a_live_bridge(
    config: BusConfig, recording: tuple[Path, list[float]]
) -> None:
    """A bridge's token in the namespace and no --keys: refused before the
    first message, naming the keys it would act on or mix with (the live
    bridge played the old trajectories again, exit 0). With --keys the
    chosen keys go out as before."""
    path, _ = recording
    with Bus.connect(config) as bridge:
        token = bridge.session.liveliness().declare_token(alive_key(TARGET, "bridge"))
        try:
            out, got = replay_into_listener(config, path, "--speed", "10")
            chosen, sent = replay_into_listener(
                config,
                path,
                *("--keys", "plan/trajectory", "--wait-for", "bridge"),
                *("--speed", "10"),
                expect=2,
            )
        finally:
            token.undeclare()
    assert out.returncode == 1
    assert out.stderr == (
        f"armplan: error: a bridge is alive in namespace {TARGET!r}: the recorded "
        "plan/request, plan/trajectory, bridge/state would go to it (a bridge "
        "with --follow moves the robot again) and mix with the live messages; "
        "nothing was sent. To replay into a live robot on purpose, choose the "
        "keys with --keys, e.g. --keys plan/trajectory --wait-for bridge\n"
    )
    assert got == []
    assert chosen.returncode == 0, chosen.stderr
    wanted = [(k, p) for k, p in payloads() if k == "plan/trajectory"]
    assert [(k, p) for k, p, _ in sent] == wanted


def test_replay_schedule_scales_with_speed() -> None:
    """In-process: sends at offset/speed, stops early on request."""
    items = [ReplayItem(o, f"k{i}", b"{}", "application/json") for i, o in
             enumerate([0.0, 0.1, 0.2])]  # fmt: skip
    sent: list[tuple[str, float]] = []
    start = time.monotonic()
    stats = replay(items, lambda k, p, e: sent.append((k, time.monotonic() - start)),
                   speed=2.0)  # fmt: skip
    assert [k for k, _ in sent] == ["k0", "k1", "k2"]
    for (_, t), item in zip(sent, items, strict=True):
        assert abs(t - item.offset / 2) < 0.02
    assert stats.sent == 3
    stop = threading.Event()
    stop.set()
    assert replay(items, lambda k, p, e: None, stop=stop).sent == 0


@pytest.mark.parametrize("speed", [0.0, -1.0, float("nan"), float("inf")])
def test_a_bad_speed_is_refused(speed: float) -> None:
    """Speed must be positive and finite."""
    with pytest.raises(InvalidInputError, match="speed must be a positive number"):
        replay([], lambda k, p, e: None, speed=speed)


def test_a_speed_whose_waits_no_timer_takes_is_refused() -> None:
    """1e-300 turned a 1 s offset into a wait past threading.TIMEOUT_MAX:
    OverflowError from the timer; now a typed error naming the speed."""
    items = [ReplayItem(o, "k", b"{}", "application/json") for o in (0.0, 1.0)]
    sent: list[str] = []
    with pytest.raises(InvalidInputError, match="speed 1e-300 is too small"):
        replay(items, lambda k, p, e: sent.append(k), speed=1e-300)
    assert sent == ["k"]  # the message at 0 s waits for nothing
    assert replay(items[:1], lambda k, p, e: None, speed=1e-300).sent == 1


def test_a_too_small_speed_is_refused_before_connecting(
    recording: tuple[Path, list[float]], capsys: pytest.CaptureFixture[str]
) -> None:
    """armplan replay --speed 1e-300: refused once the file is read, before
    any message is sent or any router is looked for."""
    from armplan.cli.main import main

    path, offsets = recording
    assert max(offsets) > 0.0
    argv = ["replay", str(path), "--speed", "1e-300", "--connect", free_endpoint()]
    assert main(argv) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert "speed 1e-300 is too small: the message at" in err
    assert "more than the longest wait" in err


def test_keys_before_the_file_say_where_the_file_went(
    recording: tuple[Path, list[float]], capsys: pytest.CaptureFixture[str]
) -> None:
    """--keys takes every word up to the next option, the file too: the error
    says so and how to write it (it said only that FILE.mcap is required);
    ended with --, or after the file, the same keys read the file."""
    from armplan.cli.main import main

    path, _ = recording
    connect = ["--connect", free_endpoint()]
    assert main(["replay", "--keys", "plan/trajectory", str(path), *connect]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert (
        f"no FILE.mcap to replay was given; --keys took {path} as one of its "
        "values (it takes every word up to the next option): give all the "
        "files first, or all of them after -- (files cannot stand on both "
        "sides of it)"
    ) in err
    for argv in (
        ["--keys", "bogus/key", "--", str(path)],
        [str(path), "--keys", "bogus/key"],
        ["--keys", "bogus/key", "--keys", "other/key", "--", str(path)],
    ):
        assert main(["replay", *connect, *argv]) == 1  # after --: files only
        err = " ".join(capsys.readouterr().err.split())
        assert "no recorded message matches --keys bogus/key" in err, argv
    assert "--keys bogus/key other/key;" in err  # repeated --keys add up


def test_an_option_after_the_double_dash_is_named_not_looked_for(
    recording: tuple[Path, list[float]], capsys: pytest.CaptureFixture[str]
) -> None:
    """`replay --keys K -- s.mcap --connect E`: after --, --connect and E are
    files; it said "--connect: no such file". Refused naming the option and
    where to put it, before any file is read or router looked for."""
    from armplan.cli.main import main

    path, _ = recording
    endpoint = free_endpoint()
    argv = ["replay", "--keys", "plan/trajectory", "--", str(path)]
    assert main([*argv, "--connect", endpoint]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert err == (
        "armplan: error: --connect was taken for a file: after --, every word "
        "is a file; give the options before -- (e.g. --keys plan/trajectory "
        "--connect tcp/HOST:PORT -- s.mcap)"
    )


def test_keys_that_take_a_later_part_say_so(
    recording: tuple[Path, list[float]], capsys: pytest.CaptureFixture[str]
) -> None:
    """`replay s-0001.mcap --keys plan/trajectory s-0002.mcap` replayed the
    first part alone, the second taken for a key matching nothing: refused,
    saying where the file went, before any file is read."""
    from armplan.cli.main import main

    path, _ = recording
    later = "rot-0002.mcap"  # a Zenoh key too; need not exist: not read
    connect = ["--connect", free_endpoint()]
    argv = ["replay", str(path), "--keys", "plan/trajectory", later, *connect]
    assert main(argv) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert (
        f"armplan: error: --keys took {later} as one of its values (it takes "
        "every word up to the next option): give all the files first, or all "
        "of them after -- (files cannot stand on both sides of it)"
    ) in err
    argv = ["replay", str(path), "--wait-for", "bridge", later, *connect]
    assert main(argv) == 1
    assert f"--wait-for took {later} as one of its values" in capsys.readouterr().err


def test_a_bad_speed_is_refused_before_connecting(
    recording: tuple[Path, list[float]], capsys: pytest.CaptureFixture[str]
) -> None:
    """armplan replay --speed 0 with no router: the speed is named, not the
    missing router."""
    from armplan.cli.main import main

    path, _ = recording
    argv = ["replay", str(path), "--speed", "0", "--connect", free_endpoint()]
    assert main(argv) == 1
    assert "speed must be a positive number" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("option", "message"),
    [(["--wait", "-1"], "--wait must be 0 or more seconds, got -1.0"),
     (["--wait", "nan"], "--wait must be 0 or more seconds, got nan"),
     (["--keys", "bogus/key"],
      "no recorded message matches --keys bogus/key; the recording holds "
      "bridge/state, misc/raw, plan/request, plan/trajectory"),
     (["--keys", f"{NAMESPACE}/plan/*"],
      f"no recorded message matches --keys {NAMESPACE}/plan/*; the recording "
      "holds bridge/state, misc/raw, plan/request, plan/trajectory; keys are "
      "relative to the namespace: give plan/*")],
)  # fmt: skip
def test_options_that_would_do_nothing_are_refused_before_connecting(
    option: list[str],
    message: str,
    recording: tuple[Path, list[float]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A negative or NaN --wait, or --keys that match nothing (once 'sent 0 of
    0 messages', exit 0): exit 1 naming the option (and the recorded keys),
    with no router there to blame."""
    from armplan.cli.main import main

    path, _ = recording
    assert main(["replay", str(path), *option, "--connect", free_endpoint()]) == 1
    assert message in capsys.readouterr().err


def test_record_refuses_an_endless_or_empty_setting(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """record --duration inf (accepted once, as if given none) and --namespace ''
    (once the default namespace, silently): exit 1 naming the option, no file."""
    from armplan.cli.main import main

    out = tmp_path / "r.mcap"
    base = ["record", "-o", str(out), "--connect", free_endpoint()]
    assert main([*base, "--duration", "inf"]) == 1
    assert "--duration must be a positive number of seconds" in capsys.readouterr().err
    assert main([*base, "--duration", "1", "--namespace", ""]) == 1
    assert "namespace '' must be chunks" in capsys.readouterr().err
    assert not out.exists()


def test_json_payloads_and_raw_bytes_come_back_identical(
    recording: tuple[Path, list[float]],
) -> None:
    """replay_items unwraps RawPayload and keeps JSON bytes as sent."""
    path, _ = recording
    items = list(replay_items(path))
    assert [(i.path, i.payload) for i in items] == payloads()
    raw = [i for i in items if i.path == "misc/raw"]
    assert raw and all(i.encoding == "zenoh/bytes" for i in raw)
    assert json.loads(items[0].payload) == {"i": 0}


def test_files_started_out_of_order_are_refused(tmp_path: Path) -> None:
    """Two recordings, the later named first: refused naming both, since
    its messages would play before the earlier ones; in order they play."""
    from services.recorder.options import RecorderOptions
    from services.recorder.routing import Incoming
    from services.recorder.sink import RecordingSink
    from shared.errors import RecordingError

    files = []
    for i in range(2):
        out = tmp_path / f"s{i}.mcap"
        sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), "ns").start()
        t = time.time_ns()
        sink.put(Incoming("ns/misc/x", b'{"i": %d}' % i, "application/json", t, t))
        sink.stop()
        files.append(out)
        time.sleep(0.01)  # the second starts later
    assert [item.payload for item in replay_items(files)] == [b'{"i": 0}', b'{"i": 1}']
    with pytest.raises(RecordingError, match=r"s0\.mcap was started before .*s1\.mcap"):
        replay_items(files[::-1])


def test_a_copy_started_at_the_same_time_is_not_called_earlier(
    tmp_path: Path,
) -> None:
    """A recording and its copy start at the same instant: the error says so
    (it said the second 'was started before' the first)."""
    from services.recorder.options import RecorderOptions
    from services.recorder.routing import Incoming
    from services.recorder.sink import RecordingSink
    from shared.errors import RecordingError

    out = tmp_path / "s.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), "ns").start()
    t = time.time_ns()
    sink.put(Incoming("ns/misc/x", b'{"i": 0}', "application/json", t, t))
    sink.stop()
    copy = tmp_path / "copy.mcap"
    copy.write_bytes(out.read_bytes())
    with pytest.raises(
        RecordingError,
        match=r"copy\.mcap was started at the same time as .*s\.mcap: give the",
    ):
        replay_items([out, copy])


def test_a_file_twice_or_a_part_left_out_is_refused(tmp_path: Path) -> None:
    """Parts 1 and 3 of a rotated recording (part 2 left out), or one file
    twice, would play with a hole or twice: refused, naming them."""
    from services.recorder.options import RecorderOptions
    from services.recorder.routing import Incoming
    from services.recorder.sink import RecordingSink
    from shared.errors import RecordingError
    from shared.recording.rotation import RotationPolicy, part_path

    out = tmp_path / "r.mcap"
    options = RecorderOptions(
        output=out, keys=("**",), rotation=RotationPolicy(max_bytes=1)
    )
    sink = RecordingSink(options, "ns").start()
    for i in range(3):
        t = time.time_ns()
        sink.put(Incoming("ns/misc/x", b'{"i": %d}' % i, "application/json", t, t))
        time.sleep(0.05)  # each message starts its own part (1 byte each)
    sink.stop()
    parts = [part_path(out, n) for n in (1, 2, 3, 4)]  # 1: the description only
    assert all(p.exists() for p in parts)
    assert len(replay_items(parts)) == 3
    with pytest.raises(RecordingError, match=r"r-0003\.mcap is part 3 .* part 2 is"):
        replay_items([parts[0], parts[2]])
    with pytest.raises(RecordingError, match=r"r-0001\.mcap is given twice"):
        replay_items([parts[0], parts[0]])


def test_two_recordings_made_at_once_are_not_replayed_as_one(tmp_path: Path) -> None:
    """A second recorder started while the first records: each file is in
    start order, but their messages interleave, so they are refused."""
    from services.recorder.options import RecorderOptions
    from services.recorder.routing import Incoming
    from services.recorder.sink import RecordingSink
    from shared.errors import RecordingError

    def sink(name: str) -> RecordingSink:
        options = RecorderOptions(output=tmp_path / name, keys=("**",))
        return RecordingSink(options, "ns").start()

    first = sink("x.mcap")
    time.sleep(0.01)
    second = sink("y.mcap")
    for i in range(3):
        t = time.time_ns()
        for each in (first, second):
            each.put(Incoming("ns/misc/x", b'{"i": %d}' % i, "application/json", t, t))
        time.sleep(0.01)
    first.stop()
    second.stop()
    with pytest.raises(RecordingError, match=r"y\.mcap overlaps .*x\.mcap"):
        replay_items([tmp_path / "x.mcap", tmp_path / "y.mcap"])


def test_an_interrupted_replay_says_so_in_its_exit_code(
    config: BusConfig, recording: tuple[Path, list[float]]
) -> None:
    """SIGINT a replay slowed tenfold (13 s) after a second: it said 'sent 2
    of 7 messages' and exited 0, so a script took it for a whole one; it now
    exits 130 and says it was interrupted."""
    path, _ = recording
    command = [sys.executable, "-m", "armplan", "replay", str(path), "--speed", "0.1"]
    command += ["--connect", config.endpoint, "--namespace", TARGET]
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    time.sleep(4.0)  # start-up, then the first messages
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=30)
    assert process.returncode == 130, err
    assert "interrupted before the end" in err
    assert f"of {len(OFFSETS)} messages" in out


@pytest.mark.parametrize("waits_for", ["router", "bridge"])
def test_ctrl_c_while_waiting_ends_the_replay_at_once(
    config: BusConfig, recording: tuple[Path, list[float]], waits_for: str
) -> None:
    """Ctrl-C while replay waited for a router (none there) or for a service
    (--wait-for bridge, never started) was ignored until the wait ran out
    (40 s), then it exited 1; it now ends the wait: 130, "interrupted"."""
    path, _ = recording
    endpoint = free_endpoint() if waits_for == "router" else config.endpoint
    command = [sys.executable, "-m", "armplan", "replay", str(path)]
    command += ["--connect", endpoint, "--namespace", NAMESPACE, "--wait", "40"]
    if waits_for == "bridge":
        command += ["--wait-for", "bridge"]
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True)
    time.sleep(4.0)  # imported, checked the file, now waiting
    process.send_signal(signal.SIGINT)
    sent = time.monotonic()
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    assert time.monotonic() - sent < 20.0, "the wait was not ended"
    assert "interrupted" in stderr


def test_a_key_not_under_a_namespace_gets_no_namespace_hint(
    recording: tuple[Path, list[float]], capsys: pytest.CaptureFixture[str]
) -> None:
    """--keys fit/** on a recording without fit/*: the hint took any first
    chunk for a namespace and said "keys are relative to the namespace:
    give **" (which replays everything). Only a key under the file's or the
    replay's namespace gets it."""
    from armplan.cli.main import main

    path, _ = recording
    argv = ["replay", str(path), "--keys", "fit/**", "--connect", free_endpoint()]
    assert main(argv) == 1
    assert capsys.readouterr().err == (
        "armplan: error: no recorded message matches --keys fit/**; the recording "
        "holds bridge/state, misc/raw, plan/request, plan/trajectory\n"
    )
    argv[3] = "armplan/plan/*"  # the replay's namespace (the file's: NAMESPACE)
    assert main(argv) == 1
    assert "relative to the namespace: give plan/*" in capsys.readouterr().err


def test_a_recording_of_nothing_is_not_replayed_as_a_whole_one(
    config: BusConfig, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A recorder stopped before anything was published writes a file with
    no messages: its replay said "sent 0 of 0 messages", exit 0, which a
    script takes for a replayed session. It is refused, naming the files,
    before any router is looked for (no router listens at the endpoint),
    as is a file holding only a channel derived for Foxglove and the
    model the recorder asked for at its start."""
    from mcap.writer import Writer

    from armplan.cli.main import main

    empty = tmp_path / "empty.mcap"
    with RecorderProcess.start(config, empty, keys=["misc/*"]):
        time.sleep(0.3)
    derived = tmp_path / "derived.mcap"
    with derived.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="another tool")
        for time_ns, topic in enumerate(["/tf/arm", "fit/model"], start=1):
            channel = writer.register_channel(topic, "json", schema_id=0)
            writer.add_message(channel, time_ns, data=b"{}", publish_time=time_ns)
        writer.finish()
    connect = ["--connect", free_endpoint(), "--wait", "0"]
    assert main(["replay", str(empty), *connect]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert f"nothing to replay: {empty} holds no recorded Zenoh messages" in err
    assert main(["replay", str(derived), str(empty), *connect]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert (
        f"{derived}, {empty} hold no recorded Zenoh messages but the recorder's "
        "own questions' answers (fit/model), which no service publishes"
    ) in err
    cut = tmp_path / "cut.mcap"  # its first message's record cut short
    cut.write_bytes(derived.read_bytes()[:100])
    assert main(["replay", str(cut), "--recover", *connect]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert f"{cut} is damaged after 0 readable messages (" in err
    assert "nothing of it is replayed; what came after is lost" in err
    assert f"nothing to replay: {cut} holds no readable recorded Zenoh" in err


def test_an_empty_file_name_is_named_not_taken_for_the_folder_here(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """`replay ""` said ". is a folder, not an MCAP file" (Path("") is ".")."""
    from armplan.cli.main import main

    assert main(["replay", ""]) == 1
    assert capsys.readouterr().err == (
        "armplan: error: a file's name is empty (''): name each MCAP file\n"
    )


def test_a_replay_stopped_early_counts_its_time_to_the_stop() -> None:
    """Stopped 0.3 s after its first message, while waiting 10 s for the
    second: it said "sent 1 of 2 messages in 0.000 s" (the time to its
    last send)."""
    items = [ReplayItem(o, "k", b"{}", "application/json") for o in (0.0, 10.0)]
    stop = threading.Event()
    timer = threading.Timer(0.3, stop.set)
    stats = replay(items, lambda k, p, e: timer.start(), stop=stop)
    assert stats.sent == 1
    assert 0.3 <= stats.duration < 5.0
