"""Demonstration files: MCAP with one JSON channel per message type.

Topics (each channel's schema is the pydantic model's JSON schema):
    ``demo/subject``  one ``DemoSubject`` per subject, first;
    ``demo/sample``   one ``DemoSample`` per sample, trial after trial.

Reading validates every message once, here, and turns any problem (missing,
empty, truncated or foreign file, a malformed message, a trial out of order
or of a single sample, a subject without samples, an arm that is not NAO's
size: ``nao_sized``) into a ``DemoFileError`` that names the file and what
is wrong.
"""

from __future__ import annotations

import shutil
import stat
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.nao_sized import nao_size_problem
from shared.demos.paths import check_distinct
from shared.demos.repeats import Register
from shared.demos.rotations import matrix_from_quaternion, quaternion_from_matrix
from shared.demos.same_person import SAME_ARM, same_arm
from shared.demos.trial import MIN_SAMPLES, DemoSet, Trial
from shared.errors import DemoFileError, InvalidInputError, RecordingError
from shared.messages.base import parse
from shared.messages.demo import DemoSample, DemoSubject
from shared.output_paths import check_output_file, written_whole
from shared.recording import MessageWriter
from shared.recording.reader import Recording
from shared.robot.side import Side
from shared.text.counted import agreeing

SUBJECT_TOPIC = "demo/subject"
SAMPLE_TOPIC = "demo/sample"
#: Gap between trials on the file's clock [ns].
_TRIAL_GAP_NS = 1_000_000_000


#: How ``armplan demos synth`` starts a file's ``source``: "synthetic, seed N"
#: (an import's source is its files' names, which may hold the word).
SYNTHETIC = "synthetic, seed "


#: Motion-capture file endings, which ``armplan demos import`` reads.
CAPTURE_SUFFIXES = (".c3d", ".csv")


def write_demos(path: str | Path, demos: DemoSet, source: str = "") -> int:
    """Write ``demos`` to an MCAP file; returns the number of samples written.

    The file is written under a ``.partial`` name and renamed when complete,
    so a failure leaves no half-written file (and an older file intact); a
    link's target is the file replaced, and a path that is no regular file
    (``/dev/null``) is written into (``shared.output_paths.written_whole``);
    a pipe by way of a temporary file (``_write_into``).

    Args:
        path: File to create (overwritten).
        demos: Subjects and trials (retargeted to NAO).
        source: Where the data came from, stored with each subject.

    Raises:
        InvalidInputError: if ``path`` is no file name, a directory, or in a
            folder that does not exist (``shared.output_paths.check_output_file``).
        DemoFileError: if a subject is not a valid ``DemoSubject`` (e.g. a
            zero-length segment), or the file would not read back: a subject
            without samples, a trial of a single sample, or one whose arm is
            not NAO's size (``nao_sized``).
        RecordingError: if the file cannot be written.
    """
    path = check_output_file(path)
    _check_every_subject_moves(demos.subjects, {t.subject for t in demos.trials}, path)
    for trial in demos.trials:
        _check_moves(trial.subject, trial.trial, trial.times, path)
        _check_nao_sized(trial, path)
    people = [_subject_message(s, source, path) for s in demos.subjects.values()]
    try:
        with written_whole(path) as partial:  # a device or FIFO: into it
            count = _write_into(partial, people, demos.trials)
    except OSError as exc:
        raise RecordingError(
            f"cannot write {path}: {exc.strerror}", path=str(path)
        ) from None
    return count


def _write_into(path: Path, people: list[DemoSubject], trials: list[Trial]) -> int:
    """:func:`_write` into ``path``; into a pipe, by way of a temporary file.

    An MCAP writer seeks (``tell``) for its summary, which a pipe refuses:
    ``demos synth -o /dev/stdout | cat > d.mcap`` sent the pipe the file's
    first 39 bytes, then failed "cannot write /dev/stdout: Illegal seek".
    The file is now written whole first, then copied into the pipe.
    """
    if not (path.exists() and stat.S_ISFIFO(path.stat().st_mode)):
        return _write(path, people, trials)
    with tempfile.TemporaryDirectory(prefix="armplan-demos-") as folder:
        whole = Path(folder) / "demos.mcap"
        count = _write(whole, people, trials)
        with whole.open("rb") as source, path.open("wb") as sink:
            shutil.copyfileobj(source, sink)
    return count


def _write(path: Path, people: list[DemoSubject], trials: list[Trial]) -> int:
    """Write the subject messages, then every trial's samples; count samples."""
    clock = 0
    with MessageWriter(path) as writer:
        for person in people:
            writer.write(SUBJECT_TOPIC, person, clock)
        # One channel lookup, then raw writes: MessageWriter.write builds the
        # class's JSON schema on every call, which costs milliseconds.
        channel = writer.channel_id(
            SAMPLE_TOPIC, DemoSample.__name__, DemoSample.json_schema()
        )
        for trial in trials:
            for sample in samples_of(trial):
                stamp = clock + round(sample.time * 1e9)
                writer.write_raw(channel, sample.to_json().encode(), stamp)
            clock += round(float(trial.times[-1]) * 1e9) + _TRIAL_GAP_NS
        return writer.count - len(people)


def _subject_message(subject: Subject, source: str, path: Path) -> DemoSubject:
    """The subject's message; an invalid one names the subject and field."""
    fields = {
        "name": subject.name,
        "stature": subject.stature if subject.stature > 0 else None,
        "upper_arm": subject.upper_arm,
        "forearm": subject.forearm,
        "source": source,
    }
    try:
        return parse(DemoSubject, fields)
    except InvalidInputError as exc:
        raise DemoFileError(
            str(path), f"not written, subject {subject.name!r}: {exc.message}"
        ) from None


def samples_of(trial: Trial) -> list[DemoSample]:
    """The messages of one trial, one per sample."""
    quats = (
        None
        if trial.wrist_frame is None
        else quaternion_from_matrix(trial.wrist_frame).tolist()
    )
    target = tuple(float(v) for v in trial.target)
    out = []
    for k, time in enumerate(trial.times.tolist()):
        out.append(
            DemoSample(
                subject=trial.subject,
                trial=trial.trial,
                point=trial.point,
                arm=trial.arm,
                time=time,
                shoulder=tuple(trial.shoulder[k].tolist()),
                elbow=tuple(trial.elbow[k].tolist()),
                wrist=tuple(trial.wrist[k].tolist()),
                wrist_orientation=None if quats is None else tuple(quats[k]),
                target=target,
                primitive=None if trial.labels is None else trial.labels[k],
            )
        )
    return out


def read_demos(paths: str | Path | Iterable[str | Path]) -> DemoSet:
    """The demonstrations in one or more MCAP files, validated.

    A subject in several files is one person if its arms agree within
    ``SAME_ARM`` (``same_person``); each trial is the first file's that has
    it, and the first file's arm is kept.

    Raises:
        DemoFileError: naming the file and the problem, if a file is given
            twice (its trials would count twice), is missing,
            empty, truncated, not MCAP, holds a malformed message or no
            samples, has a subject without samples (naming it), a trial of
            a single sample, whose samples are out of order or whose arm is
            not NAO's size (not retargeted: ``nao_sized``; naming the
            trial and its subject); if one subject's arms in two files
            differ by more than ``SAME_ARM`` (two people under one name), or
            a trial is read twice: the same samples, or one subject's trial
            number, in two files (``repeats``, naming both).
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    paths = list(paths)
    check_distinct(paths)
    subjects: dict[str, Subject] = {}
    found_in: dict[str, Path] = {}
    trials: list[Trial] = []
    register = Register()
    for path in paths:
        more, synthetic = _read_one(Path(path))
        for name, subject in more.subjects.items():
            if name in subjects:
                _check_same(subjects[name], subject, found_in[name], Path(path))
            else:
                subjects[name], found_in[name] = subject, Path(path)
        for trial in more.trials:
            register.add(trial, str(path), synthetic=synthetic)
        trials.extend(more.trials)
    return DemoSet(subjects, trials)


def _check_same(first: Subject, again: Subject, where: Path, here: Path) -> None:
    """Raise unless ``again`` is the same person as ``first`` (``same_arm``).

    Two people recorded under one name (two synthetic sets of other seeds,
    or ``reach.csv`` from two sessions without a subject in the marker map)
    were merged, the later arm replacing the earlier one. One person's arm
    measured in two imports differs by millimetres: the same person.

    Raises:
        DemoFileError: naming the subject, both files and both arms.
    """
    if same_arm(first, again):
        return
    where_text = "earlier in it" if where == here else f"in {where}"
    raise DemoFileError(
        str(here),
        f"subject {first.name!r} has arms of {again.upper_arm:.3f} + "
        f"{again.forearm:.3f} m here and {first.upper_arm:.3f} + "
        f"{first.forearm:.3f} m {where_text}, more than {SAME_ARM:.0%} apart: "
        'two people under one name? Give each its own (the marker map\'s "subject")',
    )


def _read_one(path: Path) -> tuple[DemoSet, bool]:
    """The file's demonstrations, and whether ``armplan demos synth`` made them."""
    subjects: dict[str, Subject] = {}
    synthetic = False
    samples: list[DemoSample] = []
    try:
        recording = Recording(path)
        for index, record in enumerate(recording):
            if record.topic == SUBJECT_TOPIC:
                s = _parse(DemoSubject, record.data, path, index, record.topic)
                person = Subject(s.name, s.stature or 0.0, s.upper_arm, s.forearm)
                synthetic = synthetic or s.source.startswith(SYNTHETIC)
                if s.name in subjects:
                    _check_same(subjects[s.name], person, path, path)
                subjects[s.name] = person
            elif record.topic == SAMPLE_TOPIC:
                samples.append(
                    _parse(DemoSample, record.data, path, index, SAMPLE_TOPIC)
                )
    except RecordingError as exc:
        why = _why(exc)
        if "not an MCAP file" in why:  # not missing, a folder or unreadable
            why += _capture_hint(path)
        raise DemoFileError(str(path), why) from None
    if recording.damage is not None:
        if recording.not_mcap:
            raise DemoFileError(
                str(path),
                "not an MCAP file (no MCAP magic at its start)" + _capture_hint(path),
            )
        raise DemoFileError(
            str(path),
            f"truncated or damaged after {recording.count} readable "
            f"{agreeing(recording.count, 'message')} "
            f"({recording.damage})",
            readable=recording.count,
        )
    if not samples:
        raise DemoFileError(
            str(path), f"holds no demonstration samples (topic {SAMPLE_TOPIC!r})"
        )
    return DemoSet(subjects, _trials(samples, subjects, path)), synthetic


def _capture_hint(path: Path) -> str:
    """What to do with a motion capture given as demonstrations, or ``""``.

    ``armplan fit rec.c3d`` said only "not an MCAP file", and the README's
    "demonstrations (synthetic, C3D, CSV)" suggests that fit reads them.
    """
    if path.suffix.lower() not in CAPTURE_SUFFIXES:
        return ""
    return (
        f": a {path.suffix.lower()[1:].upper()} motion capture is imported "
        "first, 'armplan demos import FILE --markers MAP.json -o demos.mcap' "
        "(docs/decision.md), and the MCAP file it writes is the demonstrations"
    )


def _why(error: RecordingError) -> str:
    """The recording error's message without its leading file name."""
    text = error.message
    prefix = f"{error.path}"
    if not text.startswith(prefix):
        return text
    return text[len(prefix) :].lstrip(": ").removeprefix("is ")


M = TypeVar("M", DemoSubject, DemoSample)


def _parse(cls: type[M], data: object, path: Path, index: int, topic: str) -> M:
    """Validate one message; a problem names the file, message and field."""
    try:
        return parse(cls, data)  # type: ignore[arg-type]
    except InvalidInputError as exc:
        raise DemoFileError(
            str(path), f"message {index} on {topic!r} is malformed: {exc.message}"
        ) from None


def _trials(
    samples: list[DemoSample], subjects: dict[str, Subject], path: Path
) -> list[Trial]:
    """Consecutive samples of one (subject, trial, arm) make one trial."""
    groups: list[list[DemoSample]] = []
    seen: set[tuple[str, str, int]] = set()
    for sample in samples:
        key = _trial_key(sample)
        if groups and _trial_key(groups[-1][0]) == key:
            groups[-1].append(sample)
            continue
        if key in seen:
            raise DemoFileError(
                str(path),
                f"the samples of trial {sample.trial} of subject {sample.subject!r} "
                f"({key[1]} arm) are not consecutive",
            )
        if sample.subject not in subjects:
            raise DemoFileError(
                str(path),
                f"samples of subject {sample.subject!r} but no {SUBJECT_TOPIC!r} "
                "record for it",
            )
        seen.add(key)
        groups.append([sample])
    _check_every_subject_moves(subjects, {key[0] for key in seen}, path)
    return [_trial(group, path) for group in groups]


def _trial_key(sample: DemoSample) -> tuple[str, str, int]:
    """Which trial a sample is of: (subject, arm, trial number)."""
    return sample.subject, Side.parse(sample.arm).value, sample.trial


def _check_every_subject_moves(
    subjects: dict[str, Subject], moving: set[str], path: Path
) -> None:
    """Refuse a subject record without a sample: a person who reached nowhere.

    Args:
        subjects: The file's subjects, by name.
        moving: The names of the subjects its samples are of.
        path: The file, for messages.
    """
    for name in subjects:
        if name not in moving:
            raise DemoFileError(
                str(path),
                f"subject {name!r} has a {SUBJECT_TOPIC!r} record but no samples",
                subject=name,
            )


def _check_moves(subject: str, trial: int, times: Any, path: Path) -> None:
    """Refuse a trial of fewer than ``MIN_SAMPLES`` samples (times [s], (n,))."""
    if len(times) < MIN_SAMPLES:
        has = (
            f"a single sample (t = {float(times[0]):g} s)"
            if len(times)
            else "no samples"
        )
        raise DemoFileError(
            str(path),
            f"trial {trial} of subject {subject!r} has {has}; a trial needs at "
            f"least {MIN_SAMPLES} samples, from its start to its goal",
            subject=subject,
            trial=trial,
        )


def _trial(group: list[DemoSample], path: Path) -> Trial:
    first = group[0]
    name = f"trial {first.trial} of subject {first.subject!r}"
    times = np.array([s.time for s in group])
    _check_moves(first.subject, first.trial, times, path)
    if len(times) > 1 and not np.all(np.diff(times) > 0):
        bad = int(np.argmin(np.diff(times) > 0)) + 1
        raise DemoFileError(
            str(path),
            f"{name}: sample {bad} (t = {times[bad]:g} s) is not after the one before",
        )
    oriented = [s.wrist_orientation is not None for s in group]
    labelled = [s.primitive is not None for s in group]
    if any(oriented) != all(oriented) or any(labelled) != all(labelled):
        raise DemoFileError(
            str(path),
            f"{name}: wrist orientations and primitive labels must be given for "
            "every sample of a trial or for none",
        )
    frames = (
        matrix_from_quaternion(np.array([s.wrist_orientation for s in group]))
        if all(oriented)
        else None
    )
    trial = Trial(
        subject=first.subject,
        trial=first.trial,
        point=first.point,
        arm=first.arm,
        times=times,
        shoulder=np.array([s.shoulder for s in group]),
        elbow=np.array([s.elbow for s in group]),
        wrist=np.array([s.wrist for s in group]),
        wrist_frame=frames,
        target=np.array(group[-1].target),
        labels=[str(s.primitive) for s in group] if all(labelled) else None,
        source=str(path),
    )
    _check_nao_sized(trial, path)
    return trial


def _check_nao_sized(trial: Trial, path: Path) -> None:
    """Refuse a trial whose arm is not NAO's size (``nao_sized``)."""
    problem = nao_size_problem(trial)
    if problem:
        raise DemoFileError(
            str(path),
            f"trial {trial.trial} of subject {trial.subject!r}: {problem}",
            subject=trial.subject,
            trial=trial.trial,
        )
