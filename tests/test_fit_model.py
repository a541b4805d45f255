"""Fitting the model and its file: tables are counts, files fail clearly."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

from services.fit import (
    MODEL_VERSION,
    MotionModel,
    default_model,
    fit_model,
    load_model,
    save_model,
)
from services.fit.conditionals import CONDITIONED
from services.fit.demo_variables import trial_variables
from services.fit.fitting import MIN_TRIALS
from shared.demos import DemoSet, Trial, nao_arm_size, synthesize
from shared.errors import InvalidInputError, ModelFileError, TooFewSamplesError


@pytest.fixture(scope="module")
def demos() -> DemoSet:
    return synthesize(3, subjects=3, trials=1)


@pytest.fixture(scope="module")
def model(demos: DemoSet) -> MotionModel:
    return fit_model(demos, bins=8, smoothing=0.5, sources=["mem"])


def test_rates_are_the_maximum_likelihood_of_the_variables(
    demos: DemoSet, model: MotionModel
) -> None:
    """Each rate is samples over the sum of that variable's values."""
    size = nao_arm_size("right")
    values = np.vstack(
        [trial_variables(t, size.upper_arm, size.forearm) for t in demos.trials]
    )
    rates = [v.rate for v in model.variables]
    np.testing.assert_allclose(rates, 1.0 / values.mean(axis=0), rtol=1e-12)
    assert all(v.loo_log_likelihood < v.log_likelihood for v in model.variables)


def test_tables_count_the_samples_plus_smoothing(
    demos: DemoSet, model: MotionModel
) -> None:
    """Each table holds n samples plus 0.5 per cell; rows normalise to 1."""
    n = demos.samples
    counts, tables = model.counts(), model.conditionals()
    for name in ("prior", "shoulder", "elbow", "wrist"):
        table = getattr(counts, name)
        assert table.sum() == pytest.approx(n + 0.5 * table.size)
    assert counts.transition.sum() == pytest.approx(
        n - len(demos.trials) + 0.5 * counts.transition.size
    )
    for name, conditioned in CONDITIONED.items():
        table = getattr(tables, name)
        sums = table.sum(axis=tuple(range(conditioned, table.ndim)))
        np.testing.assert_allclose(sums, 1.0)
    assert model.primitives[0] == "S_R E_P W_P"


def test_round_trip_through_a_file(tmp_path: pathlib.Path, model: MotionModel) -> None:
    """A saved model loads back equal."""
    path = tmp_path / "model.json"
    save_model(model, path)
    assert load_model(path) == model
    assert json.loads(path.read_text())["version"] == MODEL_VERSION


def test_shipped_default_model_loads() -> None:
    """The default model inside the package is current and complete."""
    model = default_model()
    assert model.version == MODEL_VERSION
    assert len(model.subjects) == 16 and model.samples > 100_000
    assert "S_R E_P W_P" in model.primitives


def _broken(
    tmp_path: pathlib.Path, model: MotionModel, **change: object
) -> pathlib.Path:
    data = json.loads(model.to_json())
    data.update(change)
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(data))
    return path


def test_wrong_version(tmp_path: pathlib.Path, model: MotionModel) -> None:
    """A model of another version is refused, saying which and what to do."""
    path = _broken(tmp_path, model, version=MODEL_VERSION + 98)
    with pytest.raises(ModelFileError, match=r"version 99; .* reads version 1.*refit"):
        load_model(path)


def test_truncated_file(tmp_path: pathlib.Path, model: MotionModel) -> None:
    """A file cut short is named truncated."""
    path = tmp_path / "cut.json"
    path.write_text(model.to_json()[:5000])
    with pytest.raises(ModelFileError, match="truncated"):
        load_model(path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty"),
        ("[1, 2]", "expected a JSON object"),
        ('{"bins": 3}', "no 'version' field"),
        ("{oops", "not valid JSON"),
    ],
)
def test_files_that_are_not_models(
    tmp_path: pathlib.Path, text: str, message: str
) -> None:
    """Empty, foreign or broken JSON files name their problem."""
    path = tmp_path / "model.json"
    path.write_text(text)
    with pytest.raises(ModelFileError, match=message):
        load_model(path)


def test_a_binary_file_is_no_model(tmp_path: pathlib.Path) -> None:
    """The demonstrations' MCAP given as the model (``--model demos.mcap``)
    is named no motion model; it was "cannot read it ('utf-8' codec can't
    decode byte 0x89 in position 0: invalid start byte)"."""
    path = tmp_path / "demos.mcap"
    path.write_bytes(b"\x89MCAP0\r\n" + bytes(range(256)))
    with pytest.raises(ModelFileError) as caught:
        load_model(path)
    assert caught.value.message == (
        f"{path}: not a motion model: a binary file, not the JSON armplan fit writes"
    )


def test_missing_file(tmp_path: pathlib.Path) -> None:
    """A missing model file names itself."""
    with pytest.raises(ModelFileError, match="no such motion-model file"):
        load_model(tmp_path / "none.json")


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("prior", [-1.0, 2.0, 3.0, 4.0], r"prior: count -1 at \[0\]; counts must"),
        ("shoulder", [[1.0, 2.0]], "shoulder: shape"),
        ("primitives", ["S_R E_P W_P", "W_R"], "primitives must be distinct motion"),
        ("bins", 1, "bins"),
        ("sample_rate", 1e300, "sample_rate"),  # made every decision NaN
    ],
)
def test_malformed_models_name_the_field(
    tmp_path: pathlib.Path, model: MotionModel, field: str, value: object, message: str
) -> None:
    """A model whose content is wrong names the field."""
    path = _broken(tmp_path, model, **{field: value})
    with pytest.raises(ModelFileError, match=message):
        load_model(path)


def _edited(
    model: MotionModel, table: str, value: float, everywhere: bool
) -> dict[str, object]:
    """The model's JSON with ``value`` in one cell of ``table`` (or in all)."""
    data = json.loads(model.to_json())
    cells = np.array(data[table], dtype=float)
    if everywhere:
        cells[...] = value
    else:
        cells.flat[1] = value
    data[table] = cells.tolist()
    return data


@pytest.mark.parametrize(
    ("table", "value", "everywhere", "message"),
    [
        ("start", 0.0, False, r"start: count 0 at \[1\]; counts must be positive"),
        ("elbow", 0.0, False, r"elbow: count 0 at \[0, 0, 0, 1\]; counts must"),
        ("transition", 1e308, True, "transition: counts too large: a row's sum"),
        ("shoulder", 1e308, True, "shoulder: counts too large: a row's sum"),
    ],
)
def test_counts_a_fit_never_writes_are_refused_at_load(
    tmp_path: pathlib.Path,
    model: MotionModel,
    table: str,
    value: float,
    everywhere: bool,
    message: str,
) -> None:
    """A fitted count is samples plus the smoothing: a zero count, or counts
    whose sums overflow, are refused when the file is read, naming the table
    (both passed, and every decision then died on a NaN g)."""
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(_edited(model, table, value, everywhere)))
    with pytest.raises(ModelFileError, match=message):
        load_model(path)


def test_fit_refuses_bad_options(demos: DemoSet) -> None:
    """No trials, bins out of range, or a smoothing that is not positive or
    so large that the tables' sums overflow (1e308 once made every
    probability NaN and the decision crash), are clear errors."""
    with pytest.raises(InvalidInputError, match="no demonstrations"):
        fit_model(DemoSet({}, []))
    with pytest.raises(InvalidInputError, match=r"bins must be 2\.\.64"):
        fit_model(demos, bins=1)
    for smoothing in (0.0, 1e308):
        with pytest.raises(InvalidInputError) as info:
            fit_model(demos, smoothing=smoothing)
        assert info.value.field == "smoothing"


def test_fit_refuses_times_in_milliseconds_first(demos: DemoSet) -> None:
    """Times in milliseconds are refused in the import's words, before any
    trial is fitted (the check ran after the variables and the weights)."""
    slow = DemoSet(
        demos.subjects, [t._replace(times=1000 * t.times) for t in demos.trials]
    )
    steps: list[int] = []
    with pytest.raises(InvalidInputError) as info:
        fit_model(slow, progress=lambda done, _: steps.append(done))
    assert info.value.message == (
        "the demonstrations: the times step 10 apart (median), a sample rate of "
        "0.1 Hz if they are seconds; demonstrations are sampled at 1 to 10000 Hz: "
        "these look like milliseconds: divide them by 1000 (times are in seconds)"
    )
    assert info.value.field == "times"
    assert steps == []


def _samples_of(trial: Trial, keep: list[int]) -> Trial:
    """``trial`` cut to the samples ``keep``, its goal still its last wrist."""
    frames = None if trial.wrist_frame is None else trial.wrist_frame[keep]
    return trial._replace(
        times=trial.times[keep] - trial.times[keep[0]],
        shoulder=trial.shoulder[keep],
        elbow=trial.elbow[keep],
        wrist=trial.wrist[keep],
        wrist_frame=frames,
        target=trial.wrist[keep[-1]].copy(),
        labels=None if trial.labels is None else [trial.labels[k] for k in keep],
    )


def test_a_fit_on_two_samples_is_refused(demos: DemoSet) -> None:
    """A trial of 2 samples (start and goal) has one sample that moves: the
    fit is refused naming how many are needed (it reported leave-one-out
    log-likelihoods of about -1e307)."""
    trial = demos.trials[0]
    short = DemoSet(demos.subjects, [_samples_of(trial, [0, len(trial.times) - 1])])
    with pytest.raises(TooFewSamplesError) as info:
        fit_model(short)
    assert info.value.message == (
        "2 samples in 1 trial are too few to fit: a fit needs at least 2 samples "
        "that are not their trial's last, 1 here (a trial's last sample is at its "
        "goal, where every motion variable is 0, and leave-one-out "
        "cross-validation must keep one that moves to fit each rate on)"
    )
    assert (info.value.found, info.value.needed) == (1, 2)


def test_few_moving_samples_give_defined_cross_validation(demos: DemoSet) -> None:
    """Three samples of each of ``MIN_TRIALS`` reaches (0.5 s and 0.25 s
    before the goal, and the goal: one rate for all) are enough: every
    leave-one-out log-likelihood is an ordinary number, not a floor's."""
    cut = [
        _samples_of(t, [len(t.times) - 51, len(t.times) - 26, len(t.times) - 1])
        for t in demos.trials[:MIN_TRIALS]
    ]
    model = fit_model(DemoSet(demos.subjects, cut))
    for v in model.variables:
        assert v.loo_log_likelihood is None or -10.0 < v.loo_log_likelihood < 10.0


def test_fewer_trials_than_the_floor_are_refused(demos: DemoSet) -> None:
    """One reach short of ``MIN_TRIALS`` is refused naming both counts (a
    one-trial, 3-sample recording once gave a model every plan used)."""
    few = DemoSet(demos.subjects, demos.trials[: MIN_TRIALS - 1])
    with pytest.raises(
        TooFewSamplesError, match=r"15 trials are too few .* at least 16"
    ) as info:
        fit_model(few)
    assert (info.value.found, info.value.needed) == (MIN_TRIALS - 1, MIN_TRIALS)
    assert fit_model(DemoSet(demos.subjects, demos.trials[:MIN_TRIALS])).samples > 0


def _frozen(trial: Trial, moving: bool) -> Trial:
    """``trial`` with the arm held at its goal; the elbow and wrist still
    move if ``moving`` (about the elbow only: the shoulder stays)."""
    n = len(trial.times)
    still = trial._replace(
        shoulder=np.repeat(trial.shoulder[-1:], n, 0),
        elbow=np.repeat(trial.elbow[-1:], n, 0),
        wrist=np.repeat(trial.wrist[-1:], n, 0),
        wrist_frame=None,
        labels=None,
    )
    if not moving:
        return still
    # the forearm swings about the still elbow by up to 1 rad to its goal
    angle = np.linspace(1.0, 0.0, n)[:, None]
    forearm = trial.wrist[-1] - trial.elbow[-1]
    side = np.cross(forearm, trial.elbow[-1] - trial.shoulder[-1])
    side *= np.linalg.norm(forearm) / np.linalg.norm(side)
    wrist = trial.elbow[-1] + np.cos(angle) * forearm + np.sin(angle) * side
    return still._replace(wrist=wrist)


def test_a_variable_that_never_moves_is_refused(demos: DemoSet) -> None:
    """A part of the arm that never moves gives its variable a rate of
    rounding (an elbow-only recording once gave S_R 1e11 /rad): refused,
    naming each such variable."""
    trials = [_frozen(t, moving=True) for t in demos.trials[:MIN_TRIALS]]
    with pytest.raises(TooFewSamplesError, match="do not move every part") as info:
        fit_model(DemoSet(demos.subjects, trials))
    message = info.value.message
    assert message.startswith("the demonstrations do not move every part of the arm")
    assert "E_P in 0 of" in message or "E_P in 0," in message  # the elbow stays
    assert "S_R in 0" not in message
    assert "E_R in" not in message
    assert (info.value.found, info.value.needed) == (0, 2)


def test_an_arm_held_still_is_refused_as_no_reach(demos: DemoSet) -> None:
    """Held at its goal throughout, a trial is no reach: refused naming it,
    before any variable is fitted (it was refused only for variables that
    never move, and beside reaches it was fitted, every rate doubled)."""
    still = _frozen(demos.trials[5], moving=False)._replace(trial=99)
    trials = [*demos.trials[:MIN_TRIALS], still]
    with pytest.raises(InvalidInputError) as info:
        fit_model(DemoSet(demos.subjects, trials))
    assert info.value.message.startswith(
        f"trial {still.trial} of subject {still.subject!r} lasts "
    )
    assert "its wrist ends 0.0 mm from where it starts" in info.value.message
    assert (info.value.evidence["subject"], info.value.evidence["trial"]) == (
        still.subject,
        still.trial,
    )


def test_recordings_without_orientation_leave_w_r_unobserved(demos: DemoSet) -> None:
    """Without wrist frames W_R gets no density; its table rows stay normalised."""
    blind = DemoSet(
        demos.subjects,
        [t._replace(wrist_frame=None, labels=None) for t in demos.trials],
    )
    model = fit_model(blind, bins=6)
    w_r = model.variables[-1]
    assert w_r.samples == 0 and w_r.loo_log_likelihood is None
    wrist = model.conditionals().wrist
    np.testing.assert_allclose(wrist.sum(axis=(2, 3)), 1.0)
