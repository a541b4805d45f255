"""armplan fit refuses demonstrations it would fit wrongly, naming the files.

Mixed sample rates (the network counts one step per sample) and a variable
no trial moves (a capture still at its goal throughout).
"""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from services.fit import fit_model
from services.fit.fitting import MIN_TRIALS
from shared.demos import DemoSet, read_demos, synthesize, write_demos
from shared.errors import TooFewSamplesError


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
    median rate, the 100 Hz steps counted as 1 ms ones."""
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
    """A clock 1 % fast is the same rate (as the median step tells)."""
    both = _renamed(demos, "F01", 1.01)
    model = fit_model(
        DemoSet({**demos.subjects, **both.subjects}, demos.trials + both.trials)
    )
    assert 100.0 <= model.sample_rate <= 101.0 + 1e-9


def test_a_capture_still_at_its_goal_names_its_file(
    demos: DemoSet, tmp_path: pathlib.Path
) -> None:
    """Every sample of each trial at its goal: the refusal names the file and
    says a trial must hold the reach ('E_P: every sample is zero' used to
    name no file)."""
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
    with pytest.raises(TooFewSamplesError) as caught:
        fit_model(read_demos(path))
    assert caught.value.message.endswith(
        f"No sample of the {MIN_TRIALS} trials in {path} moves S_R or E_P or E_R "
        "or W_P that far: each trial must be one reach, from its "
        "start to its goal (its last sample); a trial still at its goal "
        "throughout changes nothing: check that it holds the reach"
    )
