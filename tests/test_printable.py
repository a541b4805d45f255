"""Names from a file reach the terminal with their control characters escaped.

A crafted MCAP file whose topic holds ``ESC [2J`` (clear the screen),
colour codes and ``ESC ]0;...`` (the window's title) sent them raw to the
user's terminal: in ``armplan inspect``'s table (rich's ``escape`` escapes
markup only) and in the errors naming the channel.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from armplan_cli import armplan

from armplan.cli.main import main
from armplan.cli.output import report_error
from services.recorder.options import RecorderOptions
from services.recorder.routing import Incoming
from services.recorder.sink import RecordingSink
from shared.errors import InvalidInputError, RecordingError
from shared.printable import printable, printable_lines
from shared.recording import read_records

#: A topic that clears the screen, turns the text red and retitles the window.
EVIL = "armplan/x\x1b[2J\x1b[31mRED\x1b]0;TITLE\x07"
#: How it prints.
SHOWN = "armplan/x\\x1b[2J\\x1b[31mRED\\x1b]0;TITLE\\x07"


def test_control_characters_are_escaped_and_the_rest_kept() -> None:
    """ESC, BEL, CR, line breaks, bidi overrides as repr writes them; letters,
    accents, spaces and backslashes as they are."""
    assert printable(EVIL) == SHOWN
    assert printable("a\rb\bc\nd\u202ee\x7f\x9b") == "a\\rb\\x08c\\nd\\u202ee\\x7f\\x9b"
    for plain in ("armplan/plan/trajectory", "Bewegung/Ärmel", "a b\\c", ""):
        assert printable(plain) == plain
    assert printable(printable(EVIL)) == SHOWN  # once is enough
    assert printable_lines(f"one {EVIL}\ntwo\x1b") == f"one {SHOWN}\ntwo\\x1b"


def _cdr_file(path: Path, topic: str) -> Path:
    """A well-formed MCAP file (the mcap library's) with one cdr message."""
    from mcap.writer import Writer

    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="ros2", library="test")
        channel = writer.register_channel(
            topic=topic, message_encoding="cdr", schema_id=0
        )
        writer.add_message(channel_id=channel, log_time=1, publish_time=1, data=b"")
        writer.finish()
    return path


@pytest.fixture
def evil_recording(tmp_path: Path) -> Path:
    """A recording, by the recorder's sink, of a JSON message on :data:`EVIL`
    and a JointState-typed channel whose message names an unknown field so."""
    out = tmp_path / "evil.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), "armplan").start()
    t = time.time_ns() + 10**9
    sink.put(Incoming(EVIL, b'{"n": 1}', "", t, t))
    sink.stop()
    return out


def test_inspect_prints_a_crafted_topic_escaped(
    evil_recording: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The table shows the topic escaped, no ESC byte anywhere; --json keeps
    the name as the file gives it (JSON escapes it itself)."""
    assert main(["inspect", str(evil_recording)]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\x07" not in out
    assert SHOWN in out
    assert main(["inspect", str(evil_recording), "--json"]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out
    topics = [c["topic"] for c in json.loads(out)["channels"]]
    assert EVIL in topics


def test_the_errors_naming_a_crafted_topic_print_it_escaped(tmp_path: Path) -> None:
    """The refusal of a cdr channel (read_records, replay's check, `demos info`)
    names the channel escaped; stderr holds no ESC byte."""
    path = _cdr_file(tmp_path / "evil.mcap", "armplan/x\x1b[31mRED\x1b[0m")
    with pytest.raises(RecordingError) as raised:
        list(read_records(path, recover=True))
    assert "channel armplan/x\\x1b[31mRED\\x1b[0m has message encoding cdr" in (
        raised.value.message
    )
    out = armplan("demos", "info", str(path))
    assert out.returncode == 1
    assert "armplan/x\\x1b[31mRED\\x1b[0m" in out.stderr
    assert "\x1b" not in out.stderr and "Traceback" not in out.stderr


def test_a_command_error_quoting_a_name_prints_it_escaped(
    evil_recording: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`replay --keys zzz` names the keys the recording holds in its error
    (refused before it connects): whatever an error quotes reaches stderr
    escaped (``report_error``), and --json as the JSON of the message."""
    out = armplan("replay", str(evil_recording), "--keys", "zzz")
    assert out.returncode == 1
    assert "no recorded message matches --keys zzz" in out.stderr
    assert SHOWN.removeprefix("armplan/") in out.stderr
    assert "\x1b" not in out.stderr and "Traceback" not in out.stderr
    error = InvalidInputError(f"the recording holds {EVIL}\nsecond line")
    assert report_error(error, as_json=True) == 1
    captured = capsys.readouterr()
    assert captured.err == f"armplan: error: the recording holds {SHOWN}\nsecond line\n"
    assert json.loads(captured.out)["error"]["message"] == error.message
