"""Replay reads its files as it sends: memory bounded, bad files refused first.

Real MCAP files, written by the recorder's sink or by ``MessageWriter``
(for files the recorder would not write: damaged metadata, keys that are
not Zenoh keys, raw payloads that do not decode). The replay's memory is
measured with ``tracemalloc`` on recordings of N and 4N messages, not timed.
"""

from __future__ import annotations

import time
import tracemalloc
from pathlib import Path

import pytest

from armplan.launch import free_endpoint
from services.recorder.options import RecorderOptions
from services.recorder.replay import replay, replay_items
from services.recorder.routing import Incoming
from services.recorder.sink import RecordingSink
from shared.errors import RecordingError
from shared.recording import MessageWriter, read_records
from shared.recording.metadata import ARMPLAN_METADATA
from shared.recording.raw_payload import JSON_SCHEMA, JSON_SCHEMA_NAME, RawPayload
from shared.recording.reader import MAGIC
from shared.recording.rotation import RotationPolicy, part_path

NS = "ns"
#: One message's JSON [bytes].
BODY = 1000


def write_session(path: Path, n: int) -> None:
    """``n`` messages of ``BODY`` bytes, every other one a derived ``/tf``
    message (not replayed), in the live layout with the recorder's metadata."""
    with MessageWriter(path, chunked=False) as writer:
        writer.add_metadata(ARMPLAN_METADATA, {"namespace": NS, "part": "1"})
        sent = writer.add_channel(f"{NS}/misc/x", JSON_SCHEMA_NAME, JSON_SCHEMA)
        derived = writer.add_channel("/tf/planned", JSON_SCHEMA_NAME, JSON_SCHEMA)
        for i in range(n):
            data = b'{"i": %d, "pad": "%s"}' % (i, b"x" * BODY)
            writer.write_raw(derived if i % 2 else sent, data, 10**18 + i * 10**6)


def peak_of_replay(path: Path) -> tuple[int, int]:
    """(messages sent, peak of memory allocated [bytes]) for a whole replay."""
    sent = 0

    def publish(path: str, payload: bytes, encoding: str) -> None:
        nonlocal sent
        sent += 1

    tracemalloc.start()
    try:
        replay(replay_items(path), publish, speed=1e9)
        return sent, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_a_replays_memory_does_not_grow_with_the_recording(tmp_path: Path) -> None:
    """Every message was read, parsed and kept before the first was sent: a
    200 MB recording peaked at 1.27 GB. Four times the messages now take
    about the same memory, well under the file's size."""
    n = 2000
    files = {k: tmp_path / f"s{k}.mcap" for k in (1, 4)}
    for k, path in files.items():
        write_session(path, k * n)
    peak_of_replay(files[1])  # imports and caches, once
    sent_1, peak_1 = peak_of_replay(files[1])
    sent_4, peak_4 = peak_of_replay(files[4])
    print(f"peaks [kB]: {n} messages {peak_1 / 1e3:.0f}, {4 * n}: {peak_4 / 1e3:.0f}")
    assert (sent_1, sent_4) == (n // 2, 2 * n)
    assert peak_4 < 1.2 * peak_1 + 20_000
    assert peak_4 < files[4].stat().st_size / 20


def test_a_replay_is_counted_before_a_message_is_read(tmp_path: Path) -> None:
    """The count, the latest offset and the keys come from the quick pass;
    the messages are read as they are sent, so a file cut short after the
    pass is found then (not held from the start)."""
    path = tmp_path / "s.mcap"
    write_session(path, 10)
    items = replay_items(path)
    assert len(items) == 5
    assert items.latest == pytest.approx(8e-3)
    assert items.counts == {"misc/x": 5}
    data = path.read_bytes()
    path.write_bytes(data[: data.index(b'{"i": 4,')])
    with pytest.raises(RecordingError, match=r"s\.mcap changed while it was replayed"):
        list(items)


def rotated_parts(tmp_path: Path, notes: list[dict[str, str]]) -> list[Path]:
    """A rotated recording's parts, the k-th with the recorder's note ``notes[k]``."""
    paths = []
    for k, note in enumerate(notes, start=1):
        path = part_path(tmp_path / "r.mcap", k)
        with MessageWriter(path, chunked=False) as writer:
            writer.add_metadata(ARMPLAN_METADATA, {"namespace": NS} | note)
            channel = writer.add_channel(f"{NS}/misc/x", JSON_SCHEMA_NAME, JSON_SCHEMA)
            writer.write_raw(channel, b'{"k": %d}' % k, 10**18 + k)
        paths.append(path)
    return paths


FIRST = {"part": "1", "started_ns": "1000"}


@pytest.mark.parametrize(
    ("second", "named"),
    [({"part": "2", "started_ns": "17X4"}, "started_ns '17X4'"),
     ({"part": "two", "started_ns": "2000"}, "part 'two'"),
     ({"part": "2", "started_ns": "-5"}, "started_ns '-5'")],
)  # fmt: skip
def test_damaged_metadata_is_named_not_a_traceback(
    tmp_path: Path, second: dict[str, str], named: str
) -> None:
    """A part whose start or number is not a whole number raised ValueError
    from int(); now a RecordingError naming the file and the value."""
    parts = rotated_parts(tmp_path, [FIRST, second])
    with pytest.raises(
        RecordingError, match=rf"r-0002\.mcap: its armplan metadata gives {named}, "
    ):
        replay_items(parts)


def test_a_flipped_byte_in_metadata_with_recover_is_an_error_not_a_traceback(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The hunt's repro: a byte of part 2's started_ns changed, replayed with
    --recover (the checksum no longer matches): exit 1 naming the value."""
    from armplan.cli.main import main

    parts = rotated_parts(tmp_path, [FIRST, {"part": "2", "started_ns": "2000"}])
    data = parts[1].read_bytes()
    at = data.index(b"started_ns") + len(b"started_ns") + 4  # past its length
    parts[1].write_bytes(data[:at] + b"X" + data[at + 1 :])
    argv = ["replay", *map(str, parts), "--recover", "--connect", free_endpoint()]
    assert main(argv) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert "r-0002.mcap: its armplan metadata gives started_ns 'X000'" in err


def write_keys(path: Path, topics: list[str]) -> None:
    """One JSON message on each topic (not under a namespace)."""
    with MessageWriter(path, chunked=False) as writer:
        for i, topic in enumerate(topics):
            channel = writer.add_channel(topic, JSON_SCHEMA_NAME, JSON_SCHEMA)
            writer.write_raw(channel, b'{"i": %d}' % i, 10**18 + i * 10**8)


def test_a_recorded_key_that_is_not_a_zenoh_key_is_refused_first(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """ok/topic was published, then Zenoh's ZError came out as a traceback
    on bad#topic (and from --keys' matching); now nothing is sent and the
    error names the file and the topic. --keys leave such keys out."""
    from armplan.cli.main import main

    path = tmp_path / "craft.mcap"
    write_keys(path, ["ok/topic", "bad#topic", "a//b"])
    with pytest.raises(RecordingError, match=r"craft\.mcap: its channel 'bad#topic'"):
        replay_items(path)
    argv = ["replay", str(path), "--namespace", "rr", "--connect", free_endpoint()]
    assert main(argv) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert "its channel 'bad#topic' is not a Zenoh key" in err
    assert "its 1 message cannot be sent again; --keys can choose" in err
    for keys in (["ok/topic"], ["**"]):
        assert [i.path for i in replay_items(path, keys=keys)] == ["ok/topic"]


def test_a_changed_byte_is_found_before_anything_is_sent(tmp_path: Path) -> None:
    """A digit changed inside a message (still JSON): the quick pass checks
    the file's checksum, so the replay is refused whole; --recover sends it."""
    path = tmp_path / "s.mcap"
    write_session(path, 6)
    data = path.read_bytes()
    at = data.index(b'{"i": 2,') + 6
    path.write_bytes(data[:at] + b"7" + data[at + 1 :])
    with pytest.raises(RecordingError, match="its checksum does not match"):
        replay_items(path)
    assert [i.payload[:8] for i in replay_items(path, recover=True)] == [
        b'{"i": 0,',
        b'{"i": 7,',
        b'{"i": 4,',
    ]


@pytest.mark.parametrize("chunked", [False, True], ids=["live", "chunked"])
def test_every_truncation_replays_the_prefix_the_reader_reads(
    tmp_path: Path, chunked: bool
) -> None:
    """Cut at every byte: without recover a RecordingError or everything, with
    it exactly the messages ``read_records`` reads (the quick pass and the
    reader agree on where a file stops being whole). Cut inside the magic,
    nothing was recorded: both refuse it, recover or not."""
    whole = tmp_path / "whole.mcap"
    with MessageWriter(whole, chunked=chunked) as writer:
        writer.add_metadata(ARMPLAN_METADATA, {"namespace": NS})
        for topic in (f"{NS}/a", "/tf/planned", f"{NS}/b") * 3:
            channel = writer.add_channel(topic, JSON_SCHEMA_NAME, JSON_SCHEMA)
            writer.write_raw(channel, b'{"t": "%s"}' % topic.encode(), 10**18)
    data = whole.read_bytes()
    cut = tmp_path / "cut.mcap"
    for size in range(1, len(MAGIC)):
        cut.write_bytes(data[:size])
        with pytest.raises(RecordingError, match="inside the MCAP magic"):
            list(read_records(cut, recover=True))
        with pytest.raises(RecordingError, match="inside the MCAP magic"):
            replay_items(cut, recover=True)
    for size in range(len(MAGIC), len(data) + 1):
        cut.write_bytes(data[:size])
        expected = [
            r.raw
            for r in read_records(cut, recover=True)
            if not r.topic.startswith("/")
        ]
        assert [i.payload for i in replay_items(cut, recover=True)] == expected
        try:
            got = [i.payload for i in replay_items(cut)]
        except RecordingError:
            continue
        assert size == len(data), size
        assert len(got) == 6


def test_a_payload_keeps_the_zenoh_encoding_it_was_recorded_with(
    tmp_path: Path,
) -> None:
    """JSON objects were all sent again as application/json, whatever they
    came with; the recorder now notes each one's encoding in its channel's
    metadata (a channel per topic, schema and encoding), and a replay uses it."""
    out = tmp_path / "s.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    sent = [
        ("misc/x", b'{"i": 0}', "application/json"),
        ("misc/x", b'{"i": 1}', "zenoh/bytes"),
        ("misc/x", b'{"i": 2}', "text/plain;charset=utf-8"),
        ("misc/x", b"\x00raw", "zenoh/bytes"),
        ("plan/request", b'{"not": "a plan request"}', "zenoh/string"),
        ("misc/x", b'{"i": 3}', "zenoh/bytes"),
    ]
    for key, payload, encoding in sent:
        t = time.time_ns()
        sink.put(Incoming(f"{NS}/{key}", payload, encoding, t, t))
    sink.stop()
    got = [(i.path, i.payload, i.encoding) for i in replay_items(out)]
    assert got == sent


def test_a_recording_without_encodings_sends_json(tmp_path: Path) -> None:
    """Files recorded before the encodings were noted: application/json."""
    path = tmp_path / "old.mcap"
    write_keys(path, ["misc/x"])
    assert [i.encoding for i in replay_items(path)] == ["application/json"]


def test_a_message_that_is_not_json_is_sent_as_the_bytes_it_is(
    tmp_path: Path,
) -> None:
    """The replay does not parse messages: another writer's non-JSON bytes
    (its checksum right) go out as they are."""
    path = tmp_path / "odd.mcap"
    with MessageWriter(path, chunked=False) as writer:
        channel = writer.add_channel("misc/x", JSON_SCHEMA_NAME, JSON_SCHEMA)
        writer.write_raw(channel, b"\xffnot json", 10**18)
    assert [i.payload for i in replay_items(path)] == [b"\xffnot json"]


def test_a_raw_payload_that_does_not_decode_stops_the_replay_there(
    tmp_path: Path,
) -> None:
    """Only another writer makes one (its checksum is right): found when it
    is read to be sent, after the messages before it, as a RecordingError."""
    path = tmp_path / "raw.mcap"
    with MessageWriter(path, chunked=False) as writer:
        ok = writer.add_channel("misc/ok", JSON_SCHEMA_NAME, JSON_SCHEMA)
        writer.write_raw(ok, b'{"i": 0}', 10**18)
        raw = writer.add_channel("misc/raw", RawPayload.__name__, JSON_SCHEMA)
        bad = b'{"encoding": "zenoh/bytes", "base64": "not base64!"}'
        writer.write_raw(raw, bad, 10**18 + 1)
    items = replay_items(path)
    assert len(items) == 2
    sent = []
    with pytest.raises(RecordingError, match=r"raw\.mcap: a raw payload cannot be"):
        replay(items, lambda k, p, e: sent.append(k), speed=1e9)
    assert sent == ["misc/ok"]


def test_the_parts_of_a_rotated_recording_replay_as_one(tmp_path: Path) -> None:
    """Parts written by the sink (a message per part): each message once, in
    order, counted before any is read."""
    out = tmp_path / "r.mcap"
    options = RecorderOptions(
        output=out, keys=("**",), rotation=RotationPolicy(max_bytes=1)
    )
    sink = RecordingSink(options, NS).start()
    for i in range(3):
        t = time.time_ns()
        sink.put(Incoming(f"{NS}/misc/x", b'{"i": %d}' % i, "zenoh/bytes", t, t))
        time.sleep(0.01)
    parts = sink.stop()
    items = replay_items(parts)
    assert (len(items), items.counts) == (3, {"misc/x": 3})
    assert [i.payload for i in items] == [b'{"i": 0}', b'{"i": 1}', b'{"i": 2}']


def record_parts(out: Path, messages: int) -> list[Path]:
    """The sink's parts of one recording at ``out``, a message per part."""
    out.parent.mkdir(exist_ok=True)
    options = RecorderOptions(
        output=out, keys=("**",), rotation=RotationPolicy(max_bytes=1)
    )
    sink = RecordingSink(options, NS).start()
    for i in range(messages):
        t = time.time_ns()
        sink.put(Incoming(f"{NS}/misc/x", b'{"i": %d}' % i, "zenoh/bytes", t, t))
        time.sleep(0.01)
    return sink.stop()


def test_parts_of_two_recordings_are_refused_though_numbered_in_turn(
    tmp_path: Path,
) -> None:
    """A lab's two sessions, both ``-o s.mcap`` in two folders: session 1's
    part 2 and session 2's part 3 were started in order, numbered in turn and
    do not overlap, so they replayed as one, waiting through the hole between
    the sessions (100 s of nothing in the lab). Each part now notes its
    recording's start: a part after the first follows its own recording's."""
    one = record_parts(tmp_path / "a" / "r.mcap", 3)
    two = record_parts(tmp_path / "b" / "r.mcap", 3)
    assert len(one) >= 3 and len(two) >= 3
    with pytest.raises(
        RecordingError,
        match=r"b/r-0003\.mcap is part 3 of another recording than "
        r".*a/r-0002\.mcap \(its part 2\)",
    ):
        replay_items([one[1], two[2]])
    assert len(replay_items([*one, *two])) == 6  # two whole recordings in turn


def test_a_part_after_one_of_a_higher_number_says_two_recordings(
    tmp_path: Path,
) -> None:
    """Part 4 of one recording after part 4 of another (files of an older
    recorder, without the recording's start) was refused as 'part 5 is
    missing': no part was missing; they are of two recordings."""
    four = {"part": "4", "started_ns": "1000"}
    parts = rotated_parts(tmp_path, [four, four | {"started_ns": "2000"}])
    with pytest.raises(RecordingError, match=r"not of one recording") as raised:
        replay_items(parts)
    assert "is missing" not in str(raised.value)


def test_a_recovered_replay_says_the_file_was_damaged(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """replay --recover of a killed recording said only "sent 3 of 3
    messages", exit 0, as for a whole one: nothing told that the rest was
    lost. It now warns first, naming the file, how many messages were
    readable and what is wrong (as inspect --recover does); a whole file
    gets no such warning."""
    from armplan.cli.main import main

    whole = tmp_path / "whole.mcap"
    write_session(whole, 10)
    cut = tmp_path / "killed.mcap"
    data = whole.read_bytes()
    cut.write_bytes(data[: data.index(b'{"i": 6,') + 4])  # inside message 6
    base = ["--recover", "--wait", "0", "--connect", free_endpoint()]
    assert main(["replay", str(cut), *base]) == 1  # no router there
    err = " ".join(capsys.readouterr().err.split())
    assert (
        f"armplan replay: warning: {cut} is damaged after 6 readable messages "
        "(it ends in the middle of a record"
    ) in err
    assert "replaying those 6 (3 of them to send); what came after is lost" in err
    assert main(["replay", str(whole), *base]) == 1
    assert "damaged" not in capsys.readouterr().err


def test_a_recovered_replay_of_one_readable_message_says_it_in_the_singular(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A damaged file with one readable message was told "replaying it 1 (1
    of them to send)"."""
    from armplan.cli.main import main

    whole = tmp_path / "whole.mcap"
    write_session(whole, 4)
    cut = tmp_path / "killed.mcap"
    data = whole.read_bytes()
    cut.write_bytes(data[: data.index(b'{"i": 1,') + 4])  # inside message 1
    base = ["--recover", "--wait", "0", "--connect", free_endpoint()]
    assert main(["replay", str(cut), *base]) == 1  # no router there
    err = " ".join(capsys.readouterr().err.split())
    assert "is damaged after 1 readable message (" in err
    assert "replaying it (1 to send); what came after is lost" in err
