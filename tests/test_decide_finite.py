"""A model whose tables give no finite g is a typed error, never a NaN.

A model fitted with a smoothing of 5e-324 has probabilities that round to 0:
its log is -inf, and every g there was NaN, which died in the decision
message's validation with a pydantic traceback.
"""

from __future__ import annotations

import math
import pathlib

import pytest

from armplan.cli.main import main
from services.decide.decider import Decider
from services.fit import MotionModel, default_model, fit_model, save_model
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
    assert "armplan: error: the motion model cannot decide" in err
    assert "Traceback" not in err


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
