"""armplan fit refuses demonstrations it would fit wrongly, naming the files.

Mixed sample rates (the network counts one step per sample) and trials
that are no reach (a capture still at its goal throughout, 10 ms ones).
"""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from services.fit import fit_model
from services.fit.fitting import MIN_TRIALS
from shared.demos import DemoSet, Trial, read_demos, synthesize, write_demos
from shared.errors import InvalidInputError


@pytest.fixture(scope="module")
def demos() -> DemoSet:
    return synthesize(3, subjects=2, trials=1).only({"S01"})


def _renamed(demos: DemoSet, name: str, speed: float) -> DemoSet:
    """``demos``' person as ``name``, its times divided by ``speed``."""
    (person,) = demos.subjects.values()
    trials = [t._replace(subject=name, times=t.times / speed) for t in demos.trials]
    return DemoSet({name: person._replace(name=name)}, trials)


def test_files_at_two_sample_rates_are_refused_naming_each(
    demos: DemoSet, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """100 Hz and 1000 Hz files fitted together used to make one model at the
    median rate, the 100 Hz steps counted as 1 ms ones. (The first trial's
    rate is fitted to its times: its last sample, at the reach's end, is off
    the 100 Hz grid.)"""
    slow, fast = tmp_path / "slow.mcap", tmp_path / "fast.mcap"
    write_demos(slow, demos)
    write_demos(fast, _renamed(demos, "F01", 10.0))
    out = tmp_path / "m.json"
    assert main(["fit", str(slow), str(fast), "-o", str(out)]) == 1
    assert capsys.readouterr().err.endswith(
        f"armplan: error: the demonstrations mix sample rates: {slow} at 100 Hz; "
        f"{fast} at 1000 Hz. The motion model counts transitions from one sample "
        "to the next, as steps of one rate: fit the files of each rate apart, or "
        "resample them to one rate\n"
    )
    assert not out.exists()


def test_rates_within_two_percent_are_one_rate(demos: DemoSet) -> None:
    """A clock 1 % fast is the same rate (as the fitted step tells)."""
    both = _renamed(demos, "F01", 1.01)
    model = fit_model(
        DemoSet({**demos.subjects, **both.subjects}, demos.trials + both.trials)
    )
    assert 100.0 <= model.sample_rate <= 101.0 + 1e-9


def test_a_capture_still_at_its_goal_names_its_file(
    demos: DemoSet, tmp_path: pathlib.Path
) -> None:
    """Every sample of each trial at its goal: the refusal names the file,
    the subject and the trial ('E_P: every sample is zero' once named no
    file, and then no trial)."""
    trials = []
    for trial in demos.trials[:MIN_TRIALS]:
        n = len(trial.times)
        trials.append(
            trial._replace(
                shoulder=np.repeat(trial.shoulder[-1:], n, 0),
                elbow=np.repeat(trial.elbow[-1:], n, 0),
                wrist=np.repeat(trial.wrist[-1:], n, 0),
                wrist_frame=None,
                labels=None,
            )
        )
    path = tmp_path / "still.mcap"
    write_demos(path, DemoSet(demos.subjects, trials))
    with pytest.raises(InvalidInputError) as caught:
        fit_model(read_demos(path))
    first = demos.trials[0]
    assert caught.value.message == (
        f"{path}: trial {first.trial} of subject 'S01' lasts "
        f"{first.times[-1]:.2f} s, and its wrist ends 0.0 mm from where it "
        "starts (a reach goes at least 16.2 mm, 0.1 of NAO's arm): a still take "
        "(e.g. a calibration) or a hand shifting, not a reach. armplan fit "
        "counts only reaches, each from its start to its goal (its last "
        "sample), and fits every sample of a trial as reaching: leave this one "
        "out"
    )
    assert caught.value.evidence["source"] == str(path)


def _two_frames(trial: Trial) -> Trial:
    """``trial``'s start and goal only, 10 ms apart."""
    keep = [0, -1]
    return trial._replace(
        times=np.array([0.0, 0.01]),
        shoulder=trial.shoulder[keep],
        elbow=trial.elbow[keep],
        wrist=trial.wrist[keep],
        wrist_frame=None,
        labels=None,
    )


def test_two_frame_trials_are_no_reaches(
    demos: DemoSet, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """16 trials of 2 frames (10 ms) passed the count of 16 reaches and gave a
    one-primitive model that `decide` used for every path (and that a fit
    request would have installed): refused, naming the file and trial."""
    path = tmp_path / "two.mcap"
    write_demos(path, DemoSet(demos.subjects, [_two_frames(t) for t in demos.trials]))
    out = tmp_path / "m.json"
    assert main(["fit", str(path), "-o", str(out)]) == 1
    first = demos.trials[0]
    assert capsys.readouterr().err.endswith(
        f"armplan: error: {path}: trial {first.trial} of subject 'S01' lasts "
        "0.01 s, and its wrist moves for 0.00 s (from 0.01 s to 0.01 s), far "
        "more briefly than a person reaches (at least 0.1 s; the paper's "
        "subjects took 0.55 to 1.01 s): a fragment of a reach, or no reach. "
        "armplan fit counts only reaches, each from its start to its goal (its "
        "last sample), and fits every sample of a trial as reaching: leave this "
        "one out\n"
    )
    assert not out.exists()
