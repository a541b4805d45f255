"""``armplan inspect``: the summary of a recording, and clear errors on damage."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest
from armplan_cli import armplan

from armplan.cli.main import main
from services.recorder.options import RecorderOptions
from services.recorder.replay_parts import check_damage, look_through
from services.recorder.routing import Incoming
from services.recorder.sink import RecordingSink
from shared.errors import RecordingError
from shared.messages import JointState
from shared.recording.raw_payload import JSON_SCHEMA, JSON_SCHEMA_NAME
from shared.recording.rotation import RotatingWriter
from shared.robot import Side

NS = "armplan"
T0 = time.time_ns() + 10**9  # after the sink's start (its robot description)


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A recording: 30 joint states at 100 Hz and 3 unknown messages."""
    out = tmp_path_factory.mktemp("inspect") / "session.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    names = list(Side.RIGHT.joint_names)
    for i in range(30):
        state = JointState(time=i / 100, joint_names=names, positions=[0.1] * 5)
        t = T0 + i * 10_000_000
        sink.put(Incoming(f"{NS}/bridge/state", state.to_json().encode(), "", t, t))
    for i in range(3):
        t = T0 + i * 100_000_000
        sink.put(Incoming(f"{NS}/misc/note", b'{"n": %d}' % i, "", t, t))
    sink.stop()
    return out


def test_the_table_lists_channels_counts_and_times(
    session: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every channel with its schema, count, start, duration and rate."""
    assert main(["inspect", str(session), "--validate"]) == 0
    out = capsys.readouterr().out
    assert f"{session}: 64 messages on 4 channels, namespace armplan" in out
    lines = {line.split()[0]: line for line in out.splitlines() if "│" in line}
    state = lines["armplan/bridge/state"].split()[2::2]
    assert state[0] == "JointState"
    assert state[1:2] + state[3:] == ["30", "0.290", "100.0", "0"]
    assert "foxglove.FrameTransforms" in lines["/tf/executed"]
    assert "json" in lines["armplan/misc/note"]


def test_json_output(session: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--json: the same facts, times in ns and s."""
    assert main(["inspect", str(session), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["messages"] == 64
    assert data["damage"] is None and data["damage_code"] is None
    assert data["unread"] == []
    assert data["metadata"]["armplan"]["namespace"] == NS
    by_topic = {c["topic"]: c for c in data["channels"]}
    assert by_topic["armplan/bridge/state"]["messages"] == 30
    assert by_topic["armplan/bridge/state"]["start_ns"] == T0
    assert by_topic["armplan/bridge/state"]["duration"] == pytest.approx(0.29)
    assert by_topic["/robot_description"]["schema"] == "RobotDescription"
    assert {(c["encoding"], c["unread"]) for c in data["channels"]} == {("json", 0)}


def test_a_truncated_file_is_an_error_or_with_recover_its_prefix(
    session: Path, tmp_path: Path
) -> None:
    """Exit 1 with 'armplan: error:' and no traceback; --recover shows the prefix."""
    cut = tmp_path / "cut.mcap"
    data = session.read_bytes()
    cut.write_bytes(data[: data.index(b'{"n": 1}') + 4])
    out = armplan("inspect", str(cut))
    assert out.returncode == 1
    assert out.stderr.startswith(f"armplan: error: {cut} is damaged after ")
    assert "it ends in the middle of a record" in out.stderr
    assert "--recover (or recover=True) reads those messages" in out.stderr
    assert "Traceback" not in out.stderr
    out = armplan("inspect", str(cut), "--recover", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["damage"].startswith("it ends in the middle of a record")
    assert data["damage_code"] == "truncated"  # the words may change, not this
    counts = {c["topic"]: c["messages"] for c in data["channels"]}
    assert counts["armplan/bridge/state"] == 30
    assert counts["armplan/misc/note"] == 1


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: None, "no such file"),
        (lambda p: p.write_bytes(b""), "is empty (0 bytes), not an MCAP file"),
        (lambda p: p.write_text("not a recording\n" * 10), "is not an MCAP file"),
        (lambda p: p.write_text("hello\n"), "is not an MCAP file"),
        (lambda p: p.write_bytes(b"\x89MC"), "ends inside the MCAP magic"),
        (lambda p: p.mkdir(), "is a folder, not an MCAP file"),
    ],
)
def test_files_that_are_not_recordings(
    tmp_path: Path, make: object, message: str
) -> None:
    """Exit 1, 'armplan: error:' naming the file, even with --recover."""
    path = tmp_path / "x.mcap"
    make(path)  # type: ignore[operator]
    for extra in ([], ["--recover"]):
        out = armplan("inspect", str(path), *extra)
        assert out.returncode == 1
        assert out.stderr.startswith("armplan: error:")
        assert message in out.stderr
        assert "Traceback" not in out.stderr


def test_validate_reports_a_message_that_does_not_match_its_schema(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A typed channel holding a non-matching message: exit 1 naming it."""
    path = tmp_path / "bad.mcap"
    with RotatingWriter(path) as writer:
        schema = JointState.json_schema()
        writer.write("armplan/bridge/state", "JointState", schema, b'{"time": 0}', 1, 1)
    assert main(["inspect", str(path)]) == 0  # without --validate: just counted
    assert main(["inspect", str(path), "--validate"]) == 1
    err = capsys.readouterr().err
    assert "1 message does not match its channel's schema" in err
    assert "armplan/bridge/state (JointState): joint_names: Field required" in err


def test_validate_reports_json_that_is_not_utf8(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A json channel holding a JSON object in UTF-16 (which Python reads and
    Foxglove does not), or after a byte order mark: exit 1 naming each."""
    path = tmp_path / "utf16.mcap"
    with RotatingWriter(path) as writer:
        for data in (
            b'{"fine": 1}',
            '{"hello": "utf16"}'.encode("utf-16"),
            b'\xef\xbb\xbf{"hello": "bom"}',
        ):
            writer.write("armplan/misc/note", JSON_SCHEMA_NAME, JSON_SCHEMA, data, 1, 1)
    assert main(["inspect", str(path), "--validate"]) == 1
    err = capsys.readouterr().err
    assert "2 messages do not match their channel's schema, e.g. " in err
    assert "armplan/misc/note: not UTF-8 text (JSON in UTF-16" in err
    assert main(["inspect", str(path), "--validate", "--json"]) == 1
    problems = json.loads(capsys.readouterr().out)["problems"]
    assert [p.split(": ", 1)[1][:24] for p in problems] == [
        "not UTF-8 text (JSON in ",
        "it starts with a byte or",
    ]


def test_validate_as_json_is_one_document_with_the_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--validate --json on a bad message: exit 1, stdout one parseable JSON
    document (the inventory and the typed error), the error once on stderr."""
    path = tmp_path / "bad.mcap"
    with RotatingWriter(path) as writer:
        schema = JointState.json_schema()
        writer.write("armplan/bridge/state", "JointState", schema, b'{"time": 0}', 1, 1)
    assert main(["inspect", str(path), "--validate", "--json"]) == 1
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert data["messages"] == 1 and data["error"]["kind"] == "recording_error"
    assert captured.err.count("armplan: error:") == 1


def test_a_demonstration_file_validates(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """armplan's own demonstration files (``demos synth``) pass --validate: their
    schemas DemoSubject and DemoSample are armplan's models."""
    path = tmp_path / "demos.mcap"
    assert (
        main(["demos", "synth", "-o", str(path), "--subjects", "1", "--trials", "1"])
        == 0
    )
    capsys.readouterr()
    assert main(["inspect", str(path), "--validate", "--json"]) == 0
    channels = json.loads(capsys.readouterr().out)["channels"]
    assert {c["schema"] for c in channels} == {"DemoSubject", "DemoSample"}
    assert all(c["invalid"] == 0 for c in channels)


def _mcap(path: Path, encoding: str, messages: int) -> Path:
    """A well-formed MCAP file (not armplan's writer): one channel of ``encoding``."""
    from mcap.writer import Writer

    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="ros2" if encoding == "cdr" else "", library="test")
        schema = writer.register_schema(
            name="std_msgs/String" if encoding == "cdr" else "JointState",
            encoding="ros2msg" if encoding == "cdr" else "jsonschema",
            data=b"string data" if encoding == "cdr" else b"{}",
        )
        topic = "/chatter" if encoding == "cdr" else "armplan/bridge/state"
        channel = writer.register_channel(
            topic=topic, message_encoding=encoding, schema_id=schema
        )
        for i in range(messages):
            writer.add_message(
                channel_id=channel,
                log_time=1000 + i,
                publish_time=1000 + i,
                data=b"\x00\x01\x00\x00\x03\x00\x00\x00hi\x00",
            )
        writer.finish()
    return path


def test_a_well_formed_foreign_recording_is_listed_not_read(tmp_path: Path) -> None:
    """A ROS 2 (cdr) MCAP file is whole: inspect lists its channel and count,
    marked not read (it refused the file); reading it for its messages, as
    replay does, says it is not an armplan recording and why, not that it
    is damaged (nor that --recover helps)."""
    path = _mcap(tmp_path / "ros.mcap", "cdr", 2)
    for extra in ([], ["--recover"]):
        out = armplan("inspect", str(path), *extra)
        assert out.returncode == 0, out.stderr
        row = next(line for line in out.stdout.splitlines() if "/chatter" in line)
        cells = ["std_msgs/String", "cdr", "2", "0.000", "0.000", "-", "2"]
        assert row.split()[2::2] == cells  # the last: not read
        assert "not read: 2 messages on 1 channel that is not JSON: /chatter " in (
            out.stdout
        )
        assert "armplan replay refuses this file" in out.stdout
        assert "damaged" not in out.stdout and out.stderr == ""
    for recover in (False, True):
        with pytest.raises(RecordingError) as raised:
            check_damage(look_through(path), recover)  # what replay does
        assert raised.value.message == (
            f"{path} is not an armplan recording: channel /chatter has message "
            "encoding cdr, not json (armplan records JSON messages)"
        )


def _mixed(path: Path) -> Path:
    """10 JSON messages and, among them, one on a cdr channel (mcap's writer)."""
    from mcap.writer import Writer

    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="test")
        schema = writer.register_schema(JSON_SCHEMA_NAME, "jsonschema", b"{}")
        ours = writer.register_channel(
            topic="armplan/misc/note", message_encoding="json", schema_id=schema
        )
        ros = writer.register_channel(topic="/r", message_encoding="cdr", schema_id=0)
        for i in range(10):
            t = 10**9 + i * 10**6
            writer.add_message(ours, log_time=t, publish_time=t, data=b'{"x": 1}')
            if i == 4:
                writer.add_message(ros, log_time=t, publish_time=t, data=b"\0\1")
        writer.finish()
    return path


def test_a_file_with_one_foreign_channel_is_listed_whole(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """10 JSON messages and one cdr one: every channel listed, the cdr one
    not read (inspect refused the whole file, even with --recover); --json
    gives each channel's encoding and unread count, and no damage."""
    path = _mixed(tmp_path / "mixed.mcap")
    assert main(["inspect", str(path), "--recover"]) == 0
    out = capsys.readouterr().out
    assert f"{path}: 11 messages on 2 channels" in out
    rows = {line.split()[0]: line.split() for line in out.splitlines() if "│" in line}
    note = ["json", "json", "10", "0.000", "0.009", "1000.0", "0"]  # last: not read
    assert rows["armplan/misc/note"][2::2] == note
    assert rows["/r"][2::2] == ["-", "cdr", "1", "0.004", "0.000", "-", "1"]
    assert main(["inspect", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["damage"] is None and data["damage_code"] is None
    assert [
        (c["topic"], c["encoding"], c["messages"], c["unread"])
        for c in data["channels"]
    ] == [("armplan/misc/note", "json", 10, 0), ("/r", "cdr", 1, 1)]
    assert main(["inspect", str(path), "--validate", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)  # cdr: no armplan message
    assert [c["invalid"] for c in data["channels"]] == [0, 1]
    assert data["problems"] == ["/r: message encoding cdr, not json"]


def _json_channel(path: Path, *messages: bytes) -> Path:
    """A well-formed MCAP file (mcap's writer), ``messages`` on one JSON channel."""
    from mcap.writer import Writer

    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="test")
        schema = writer.register_schema(JSON_SCHEMA_NAME, "jsonschema", b"{}")
        channel = writer.register_channel(
            topic="armplan/misc/note", message_encoding="json", schema_id=schema
        )
        for i, data in enumerate(messages, start=1):
            writer.add_message(channel, log_time=i, publish_time=i, data=data)
        writer.finish()
    return path


@pytest.mark.parametrize(
    ("data", "why"),
    [
        (b"", "is empty (0 bytes)"),
        (b'{"a":' + b"[" * 200_000 + b"]" * 200_000 + b"}", "is JSON nested too deep"),
        (b"\xff{}", "is not UTF-8 text"),
    ],
    ids=["empty", "deep", "binary"],
)
def test_a_message_that_is_not_json_is_counted_not_damage(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], data: bytes, why: str
) -> None:
    """A well-formed file with a message that is not JSON (which replay sends
    as it is) was "damaged after 0 readable messages" (a deep one: "bytes
    that are not MCAP records"): every message is counted, that one not
    read and named; --validate fails naming it."""
    path = _json_channel(tmp_path / "x.mcap", b'{"n": 1}', data, b'{"n": 3}')
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert f"{path}: 3 messages on 1 channel" in out and "damaged" not in out
    row = next(line for line in out.splitlines() if "armplan/misc/note" in line)
    assert row.split()[-1] == "1"  # not read
    said = "message 2 of the file (channel armplan/misc/note, log time 2 ns) " + why
    assert "not read: 1 message on JSON channels that is not JSON, e.g. " in out
    assert said in " ".join(out.split())
    assert main(["inspect", str(path), "--validate"]) == 1
    assert "armplan/misc/note: " + why.removeprefix("is ") in capsys.readouterr().err


def test_a_channel_without_messages_is_listed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A file that declares a channel and holds no message: 1 channel, 0
    messages, no times (it said 0 channels)."""
    path = _mcap(tmp_path / "quiet.mcap", "json", 0)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert f"{path}: 0 messages on 1 channel," in out
    row = next(line for line in out.splitlines() if "armplan/bridge/state" in line)
    assert row.split()[2::2] == ["JointState", "0", "-", "-", "-"]
    assert main(["inspect", str(path), "--json"]) == 0
    (channel,) = json.loads(capsys.readouterr().out)["channels"]
    assert channel["messages"] == 0 and channel["start_ns"] is None


def test_a_closed_pipe_ends_the_table_quietly_with_exit_0(session: Path) -> None:
    """`armplan inspect f.mcap | head`: the reader leaves before the table is
    written; rich made that exit 1, other tools (and armplan's own writes)
    exit 0 without a word."""
    process = subprocess.Popen(
        [sys.executable, "-m", "armplan", "inspect", str(session)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()  # long before its first write (it starts Python)
    assert process.wait(timeout=60) == 0
    assert process.stderr.read() == b""
    process.stderr.close()


def test_the_docs_list_every_damage_code() -> None:
    """The docs' table of `damage_code` names every code the reader can give
    (it lacked `not_json` and `foreign`), and no other."""
    from shared.recording.reader import DAMAGE_CODES, FOREIGN

    docs = (Path(__file__).parents[1] / "docs" / "recording.md").read_text()
    row = next(line for line in docs.splitlines() if line.startswith("| `damage_code`"))
    named = set(re.findall(r"`([a-z_0-9]+)` \(", row))
    assert named == {*DAMAGE_CODES.values(), FOREIGN}


def _text_not_utf8(path: Path, where: bytes, chunked: bool) -> Path:
    """A JSON message, then a channel whose ``where`` (topic, schema name,
    the header's library, or the chunks' compression) is not UTF-8, and a
    message on it (unchunked: the bytes are changed in place, before any
    checksum is read)."""
    from mcap.writer import CompressionType, Writer

    with path.open("wb") as stream:
        writer = Writer(stream, use_chunking=chunked, compression=CompressionType.ZSTD)
        writer.start(profile="", library="Llll")
        ours = writer.register_channel("armplan/misc/note", "json", 0)
        writer.add_message(ours, log_time=1, publish_time=1, data=b'{"n": 1}')
        schema = writer.register_schema("Qqqq", "jsonschema", b"{}")
        theirs = writer.register_channel("/zzzz", "json", schema)
        writer.add_message(theirs, log_time=2, publish_time=2, data=b'{"n": 2}')
        writer.finish()
    path.write_bytes(path.read_bytes().replace(where, b"\xff\xfe\xfd\xfc"))
    return path


@pytest.mark.parametrize(
    ("where", "chunked", "readable"),
    [
        (b"zzzz", False, 1),
        (b"Qqqq", False, 1),
        (b"Llll", False, 0),
        (b"zstd", True, 0),
    ],
    ids=["topic", "schema", "header", "chunk"],
)
def test_text_not_utf8_in_a_record_is_not_called_a_message(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    where: bytes,
    chunked: bool,
    readable: int,
) -> None:
    """A channel's topic or a schema's name that is not UTF-8 was "a message
    in it is not UTF-8 JSON" (`not_json`): it names the records, `not_utf8`;
    not only channels, schemas and metadata (the header's library and a
    chunk's compression were said to be one of those)."""
    path = _text_not_utf8(tmp_path / "x.mcap", where, chunked)
    said = (
        "a record in it other than a message (its header, a channel, a schema, "
        "metadata, a chunk or an index) holds text that is not UTF-8"
    )
    noun, those = {0: ("messages", "those"), 1: ("message", "that")}[readable]
    assert main(["inspect", str(path)]) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {path} is damaged after {readable} readable {noun}: "
        f"{said}; --recover (or recover=True) reads {those} {noun}\n"
    )
    assert main(["inspect", str(path), "--recover", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["damage"], data["damage_code"]) == (said, "not_utf8")


def test_messages_replay_does_not_send_are_not_said_to_be_sent(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Messages that are not JSON on a `/...` channel (another tool's, or a
    Foxglove one): replay sends no such channel, and the note said it sent
    them as they are."""
    from mcap.writer import Writer

    path = tmp_path / "camera.mcap"
    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="test")
        ours = writer.register_channel("armplan/misc/note", "json", 0)
        camera = writer.register_channel("/camera/info", "json", 0)
        for i, (channel, data) in enumerate(
            [(ours, b""), (camera, b"\xff"), (camera, b"")], start=1
        ):
            writer.add_message(channel, log_time=i, publish_time=i, data=data)
        writer.finish()
    assert main(["inspect", str(path)]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert (
        "armplan replay sends the 1 on its keys as they are, not the 2 on "
        "channels named /..."
    ) in out


def test_an_empty_file_name_is_named_not_taken_for_the_folder_here(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """`inspect ""` said ". is a folder, not an MCAP file" (Path("") is ".")."""
    for extra in ([], ["--recover"]):
        assert main(["inspect", "", *extra]) == 1
        assert capsys.readouterr().err == (
            "armplan: error: the recording's name is empty: name an MCAP file\n"
        )
