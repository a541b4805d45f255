"""Demonstration MCAP files: round trips and clear errors for bad files."""

from __future__ import annotations

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from shared.demos import DemoSet, read_demos, synthesize, write_demos
from shared.demos.demo_file import SAMPLE_TOPIC, SUBJECT_TOPIC, samples_of
from shared.errors import DemoFileError
from shared.messages.demo import DemoSample, DemoSubject
from shared.recording import MessageWriter


@pytest.fixture(scope="module")
def small() -> DemoSet:
    return synthesize(5, subjects=2, trials=1, points=(1, 16))


@pytest.fixture
def good(tmp_path: pathlib.Path, small: DemoSet) -> pathlib.Path:
    path = tmp_path / "demos.mcap"
    write_demos(path, small, source="test")
    return path


def test_round_trip_keeps_every_sample(good: pathlib.Path, small: DemoSet) -> None:
    """Subjects, trials, positions, orientations and labels come back."""
    back = read_demos(good)
    assert back.subjects == small.subjects
    assert len(back.trials) == len(small.trials)
    for a, b in zip(small.trials, back.trials, strict=True):
        assert (a.subject, a.trial, a.point, a.arm) == (
            b.subject,
            b.trial,
            b.point,
            b.arm,
        )
        np.testing.assert_allclose(b.times, a.times)
        np.testing.assert_allclose(b.wrist, a.wrist)
        np.testing.assert_allclose(b.target, a.target)
        assert a.wrist_frame is not None and b.wrist_frame is not None
        np.testing.assert_allclose(b.wrist_frame, a.wrist_frame, atol=1e-12)
        assert a.labels == b.labels


def test_channels_carry_the_models_json_schemas(good: pathlib.Path) -> None:
    """Each topic's schema is its pydantic model's JSON schema."""
    from mcap.reader import make_reader

    with open(good, "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    by_topic = {
        c.topic: summary.schemas[c.schema_id] for c in summary.channels.values()
    }
    assert json.loads(by_topic[SAMPLE_TOPIC].data) == DemoSample.json_schema()
    assert json.loads(by_topic[SUBJECT_TOPIC].data) == DemoSubject.json_schema()


def test_empty_file(tmp_path: pathlib.Path) -> None:
    """An empty file is named as such."""
    path = tmp_path / "empty.mcap"
    path.write_bytes(b"")
    with pytest.raises(DemoFileError, match="empty"):
        read_demos(path)


def test_missing_file(tmp_path: pathlib.Path) -> None:
    """A missing file names itself."""
    with pytest.raises(DemoFileError, match="no such file"):
        read_demos(tmp_path / "nothing.mcap")


def test_truncated_file(tmp_path: pathlib.Path, good: pathlib.Path) -> None:
    """A file cut in the middle says it is truncated and what was readable."""
    data = good.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(DemoFileError, match="truncated") as caught:
        read_demos(cut)
    assert caught.value.path == str(cut)


def test_not_mcap(tmp_path: pathlib.Path) -> None:
    """A file that is not MCAP says so."""
    path = tmp_path / "garbage.mcap"
    path.write_bytes(b"this is not an MCAP file at all" * 10)
    with pytest.raises(DemoFileError, match="not an MCAP file"):
        read_demos(path)


def _write(path: pathlib.Path, subjects: list[DemoSubject], raw: list[bytes]) -> None:
    with MessageWriter(path) as writer:
        for s in subjects:
            writer.write(SUBJECT_TOPIC, s, 0)
        channel = writer.channel_id(
            SAMPLE_TOPIC, DemoSample.__name__, DemoSample.json_schema()
        )
        for i, data in enumerate(raw):
            writer.write_raw(channel, data, i)


SUBJECT = DemoSubject(name="S01", upper_arm=0.33, forearm=0.26)


def test_malformed_sample_names_message_and_field(
    tmp_path: pathlib.Path, small: DemoSet
) -> None:
    """A sample missing a field: the error names the message and the field."""
    good = samples_of(small.trials[0])[0].model_dump(mode="json")
    bad = dict(good)
    del bad["wrist"]
    path = tmp_path / "malformed.mcap"
    _write(
        path,
        [SUBJECT],
        [json.dumps(good).encode(), json.dumps(bad).encode()],
    )
    with pytest.raises(DemoFileError, match=r"message 2 .*malformed.*wrist"):
        read_demos(path)


def test_file_without_samples(tmp_path: pathlib.Path) -> None:
    """Subjects but no samples is an error naming the topic."""
    path = tmp_path / "nosamples.mcap"
    _write(path, [SUBJECT], [])
    with pytest.raises(DemoFileError, match="no demonstration samples"):
        read_demos(path)


def test_trial_out_of_order(tmp_path: pathlib.Path, small: DemoSet) -> None:
    """A trial whose samples come back after another trial is refused."""
    a = samples_of(small.trials[0])[:2]
    b = samples_of(small.trials[1])[:2]
    path = tmp_path / "order.mcap"
    subjects = [DemoSubject(name=a[0].subject, upper_arm=0.3, forearm=0.25)]
    _write(path, subjects, [s.to_json().encode() for s in (a[0], b[0], a[1])])
    with pytest.raises(DemoFileError, match="not consecutive"):
        read_demos(path)


def test_sample_without_its_subject(tmp_path: pathlib.Path, small: DemoSet) -> None:
    """Samples of a subject with no demo/subject record are refused."""
    path = tmp_path / "nosubject.mcap"
    _write(path, [], [s.to_json().encode() for s in samples_of(small.trials[0])])
    with pytest.raises(DemoFileError, match="no 'demo/subject' record"):
        read_demos(path)


def test_a_subject_without_samples_is_refused(
    tmp_path: pathlib.Path, small: DemoSet
) -> None:
    """A subject record with no sample of that subject is refused, naming the
    subject and file (it was read as a subject with no trials)."""
    path = tmp_path / "idle.mcap"
    samples = samples_of(small.trials[0])
    idle = DemoSubject(name="S99", upper_arm=0.3, forearm=0.25)
    subject = DemoSubject(name=samples[0].subject, upper_arm=0.3, forearm=0.25)
    _write(path, [subject, idle], [s.to_json().encode() for s in samples])
    with pytest.raises(DemoFileError) as caught:
        read_demos(path)
    assert caught.value.message == (
        f"{path}: subject 'S99' has a 'demo/subject' record but no samples"
    )
    assert caught.value.evidence["subject"] == "S99"


def test_a_one_sample_trial_is_refused(tmp_path: pathlib.Path, small: DemoSet) -> None:
    """A trial of one sample shows no movement: refused naming the trial, its
    subject and the file (it was read, and fitted, as a trial)."""
    path = tmp_path / "short.mcap"
    first, second = samples_of(small.trials[0]), samples_of(small.trials[1])
    subject = DemoSubject(name=first[0].subject, upper_arm=0.3, forearm=0.25)
    _write(path, [subject], [s.to_json().encode() for s in [*first, second[0]]])
    with pytest.raises(DemoFileError) as caught:
        read_demos(path)
    name = f"trial {second[0].trial} of subject {second[0].subject!r}"
    assert caught.value.message == (
        f"{path}: {name} has a single sample (t = {second[0].time:g} s); a trial "
        "needs at least 2 samples, from its start to its goal"
    )
    assert caught.value.evidence["trial"] == second[0].trial


def test_what_would_not_read_back_is_not_written(
    tmp_path: pathlib.Path, small: DemoSet
) -> None:
    """write_demos refuses, and writes no file for, a subject without trials
    and a one-sample trial: the reading refuses both, so a file of them could
    not be read back."""
    first = small.trials[0]
    idle = small.subjects[first.subject]._replace(name="S99")
    cases = {
        "idle.mcap": (
            DemoSet(small.subjects | {"S99": idle}, small.trials),
            "subject 'S99' has a 'demo/subject' record but no samples",
        ),
        "short.mcap": (
            DemoSet(
                {first.subject: small.subjects[first.subject]},
                [first._replace(times=first.times[:1])],
            ),
            f"trial {first.trial} of subject {first.subject!r} has a single sample",
        ),
    }
    for name, (demos, words) in cases.items():
        with pytest.raises(DemoFileError, match=words):
            write_demos(tmp_path / name, demos)
        assert not (tmp_path / name).exists()


def test_cli_reports_a_bad_file_without_traceback(tmp_path: pathlib.Path) -> None:
    """armplan demos info on a broken file: exit 1, one clear line, no traceback."""
    path = tmp_path / "broken.mcap"
    path.write_bytes(b"\x89MCAP0\r\n" + b"\x00" * 40)
    out = subprocess.run(
        [sys.executable, "-m", "armplan", "demos", "info", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert out.returncode == 1
    assert "Traceback" not in out.stderr
    assert out.stderr.startswith(f"armplan: error: {path}")


def test_writing_through_a_link_replaces_its_target(
    tmp_path: pathlib.Path, small: DemoSet
) -> None:
    """``-o latest.mcap``, a link to a session's file: the link was replaced
    by a regular file (and, run as root, ``-o /dev/null`` the device); now
    the link stays and its target holds the demonstrations."""
    session = tmp_path / "session-1.mcap"
    session.write_bytes(b"older")
    link = tmp_path / "latest.mcap"
    link.symlink_to(session.name)
    count = write_demos(link, small)
    assert link.is_symlink()
    assert read_demos(session).samples == count
    assert sorted(p.name for p in tmp_path.iterdir()) == [link.name, session.name]
