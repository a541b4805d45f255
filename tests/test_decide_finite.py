"""A model whose tables give no finite g is a typed error, never a NaN.

A model fitted with a smoothing of 5e-324 has probabilities that round to 0:
its log is -inf, and every g there was NaN, which died in the decision
message's validation with a pydantic traceback.
"""

from __future__ import annotations

import json
import math
import pathlib

import pytest

from armplan.cli.main import main
from services.decide.decider import Decider
from services.fit import (
    MotionModel,
    default_model,
    fit_model,
    load_model,
    save_model,
)
from shared.demos import synthesize
from shared.errors import InvalidInputError

TARGET = ["0.12", "-0.09", "0.05"]


@pytest.fixture(scope="module")
def vanishing() -> MotionModel:
    """A model fitted with a smoothing so small its unseen cells are 0."""
    return fit_model(synthesize(9, subjects=3, trials=1), bins=10, smoothing=5e-324)


def test_a_table_with_a_zero_probability_is_refused_when_compiled(
    vanishing: MotionModel,
) -> None:
    """The decider names the table instead of deciding NaN."""
    with pytest.raises(InvalidInputError) as info:
        Decider(vanishing)
    assert info.value.field == "model"
    assert "its transition table holds a probability of 0" in info.value.message


def test_decide_with_such_a_model_file_is_an_error_not_a_traceback(
    vanishing: MotionModel,
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``armplan decide --model`` exits 1 with the typed error's message."""
    path = tmp_path / "vanishing.json"
    save_model(vanishing, path)
    assert main(["decide", "--target", *TARGET, "--model", str(path)]) == 1
    err = capsys.readouterr().err
    assert "the motion model cannot decide" in err
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "command",
    [
        ["plan", "--target", *TARGET],
        ["decide", "--target", *TARGET],
        ["experiment", "pace", "--reaches", "1", "--chains", "1"],
    ],
    ids=["plan", "decide", "experiment"],
)
def test_a_model_file_that_cannot_decide_is_named(
    command: list[str],
    vanishing: MotionModel,
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Each in-process ``--model`` refuses such a file naming it, before any
    work (it said only "the motion model cannot decide"): nothing written."""
    path = tmp_path / "vanishing.json"
    save_model(vanishing, path)
    out = tmp_path / "out"
    extra = ["--out", str(out)] if command[0] == "experiment" else []
    assert main([*command, "--model", str(path), *extra]) == 1
    err = capsys.readouterr().err
    assert err.startswith(
        f"armplan: error: {path}: the motion model cannot decide: its "
    ), err
    assert not out.exists()


def test_fit_refuses_to_write_a_model_that_cannot_decide(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``armplan fit`` with a smoothing of 5e-324 exits 1 naming why and
    writes nothing (it wrote the model, exit 0, which every ``--model``
    then refused); the same demonstrations with the default smoothing fit."""
    demos = tmp_path / "demos.mcap"
    synth = ["--seed", "9", "--subjects", "3", "--trials", "1"]
    assert main(["demos", "synth", "-o", str(demos), *synth]) == 0
    out = tmp_path / "vanish.json"
    fit = ["fit", str(demos), "-o", str(out), "--bins", "10", "--json"]
    capsys.readouterr()
    assert main([*fit, "--smoothing", "5e-324"]) == 1
    assert not out.exists()
    error = json.loads(capsys.readouterr().out)["error"]
    assert error["message"].startswith(
        f"the model fitted (bins 10, smoothing 5e-324) is not written to {out}: "
        "the motion model cannot decide: its "
    )
    assert error["evidence"]["field"] == "smoothing"
    assert main(fit) == 0
    Decider(load_model(out))  # the decision can use what was written


def test_a_g_that_is_not_finite_is_a_typed_error() -> None:
    """Should a table still hold a non-finite log, decide raises, naming the
    states, rather than hand a NaN g on."""
    decider = Decider(default_model())
    values = (0.1, 0.1, 0.1, 0.1, 0.1)
    assert all(math.isfinite(g) for g in decider.decide(values, False).g)
    decider.log_start = [math.inf] * len(decider.log_start)
    with pytest.raises(InvalidInputError, match="gave no finite g at states") as info:
        decider.decide(values, False)
    assert info.value.field == "model"
