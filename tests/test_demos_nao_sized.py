"""A demonstration file's arms must be NAO's size (retargeted), or it is refused.

docs/decision.md documents the file format so a lab may write its own
converter; files written with human arm lengths or in millimetres were read
and fitted without a word (E_P's rate 0.795 or 0.0019 instead of 5.29).
"""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from shared.demos import (
    DemoSet,
    Trial,
    nao_arm_size,
    read_demos,
    synthesize,
    write_demos,
)
from shared.demos.demo_file import SAMPLE_TOPIC, SUBJECT_TOPIC, samples_of
from shared.demos.nao_sized import NAO_SIZE_TOLERANCE
from shared.errors import DemoFileError
from shared.messages.demo import DemoSubject
from shared.recording import MessageWriter


@pytest.fixture(scope="module")
def small() -> DemoSet:
    return synthesize(5, subjects=1, trials=1, points=(1, 16))


def _scaled(trial: Trial, k: float, shift: float = 0.0) -> Trial:
    """``trial`` with its arm ``k`` times as long about the shoulder, all
    moved ``shift`` [m] along x."""
    s = trial.shoulder
    move = np.array([shift, 0.0, 0.0])
    return trial._replace(
        shoulder=s + move,
        elbow=s + k * (trial.elbow - s) + move,
        wrist=s + k * (trial.wrist - s) + move,
    )


def _write_raw(path: pathlib.Path, demos: DemoSet) -> None:
    """Write ``demos`` as a lab's own converter would: no checks."""
    with MessageWriter(path) as writer:
        for person in demos.subjects.values():
            subject = DemoSubject(
                name=person.name, upper_arm=person.upper_arm, forearm=person.forearm
            )
            writer.write(SUBJECT_TOPIC, subject, 0)
        clock = 0
        for trial in demos.trials:
            for sample in samples_of(trial):
                clock += 1
                writer.write(SAMPLE_TOPIC, sample, clock)


@pytest.mark.parametrize(
    ("k", "shift", "words"),
    [
        (3.0, 0.0, "its upper arm is 0.3182 m long at sample 0, 3 times NAO's"),
        (1000.0, 0.0, "1000 times NAO's 0.1061 m (millimetres?)"),
        (1.0, 0.01, "its shoulder is at (0.01, -0.098, 0.1) m at sample 0, 0.01 m"),
    ],
    ids=["human-size", "millimetres", "shoulder-moved"],
)
def test_a_file_not_retargeted_to_nao_is_refused(
    tmp_path: pathlib.Path, small: DemoSet, k: float, shift: float, words: str
) -> None:
    """The reading names the file, the trial, its subject and what is off."""
    path = tmp_path / "lab.mcap"
    trials = [small.trials[0], _scaled(small.trials[1], k, shift)]
    _write_raw(path, DemoSet(small.subjects, trials))
    with pytest.raises(DemoFileError) as caught:
        read_demos(path)
    second = small.trials[1]
    assert caught.value.message.startswith(
        f"{path}: trial {second.trial} of subject {second.subject!r}: "
    )
    assert words in caught.value.message
    assert "retargeted to NAO" in caught.value.message
    assert caught.value.evidence["trial"] == second.trial
    with pytest.raises(DemoFileError, match=words.replace("(", r"\(")[:30]):
        write_demos(tmp_path / "again.mcap", DemoSet(small.subjects, trials))
    assert not (tmp_path / "again.mcap").exists()


def test_fit_refuses_it_without_writing_a_model(
    tmp_path: pathlib.Path, small: DemoSet, capsys: pytest.CaptureFixture[str]
) -> None:
    """``armplan fit`` on a human-size file: exit 1, no model written."""
    path, model = tmp_path / "lab.mcap", tmp_path / "model.json"
    _write_raw(path, DemoSet(small.subjects, [_scaled(t, 3.0) for t in small.trials]))
    assert main(["fit", str(path), "-o", str(model)]) == 1
    assert "its upper arm is 0.3182 m long" in capsys.readouterr().err
    assert not model.exists()


def test_positions_rounded_to_a_millimetre_are_still_nao(
    tmp_path: pathlib.Path, small: DemoSet
) -> None:
    """A converter that writes millimetres of precision passes: the check is
    for other sizes and units, not for rounding."""
    rounded = [
        t._replace(
            shoulder=np.round(t.shoulder, 3),
            elbow=np.round(t.elbow, 3),
            wrist=np.round(t.wrist, 3),
        )
        for t in small.trials
    ]
    size = nao_arm_size("right")
    off = max(
        float(
            np.max(
                np.abs(np.linalg.norm(t.elbow - t.shoulder, axis=1) - size.upper_arm)
            )
        )
        for t in rounded
    )
    assert 0.0 < off < NAO_SIZE_TOLERANCE
    path = tmp_path / "rounded.mcap"
    _write_raw(path, DemoSet(small.subjects, rounded))
    assert len(read_demos(path).trials) == len(small.trials)
