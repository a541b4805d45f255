"""A motion model the decision can use: checked before the fit service serves it.

The decide service compiles every model the fit service serves
(``services.decide.decider.Decider``) and refuses one whose tables hold a
probability that rounds to 0 (a fit with a smoothing of 5e-324). The fit
service used to serve, keep and publish such a model all the same: decide
logged "ignored a published model" and kept its old one, so ``fit/model``
and the decisions silently disagreed, and a restarted decide service could
not start on it. So the fit service compiles a model the same way, once,
before it installs a fitted one (``check_decidable``) and when it reads
one at start (``load_decidable``: ``--model``, its state file, and
``armplan up --model``).
"""

from __future__ import annotations

from pathlib import Path

from services.decide.decider import Decider
from services.fit.model import MotionModel
from services.fit.model_file import load_model
from shared.errors import InvalidInputError, ModelFileError


def check_decidable(model: MotionModel) -> None:
    """Raise if the decision cannot compile ``model``.

    Raises:
        InvalidInputError: (field ``model``, evidence ``table``) naming the
            table that holds a probability of 0 or not finite, as the decide
            service would.
    """
    Decider(model)


def load_decidable(path: str | Path) -> MotionModel:
    """The motion model in ``path``, checked that the decision can use it.

    Raises:
        ModelFileError: naming the file and the problem: those of
            ``load_model``, or a model the decision cannot compile (naming
            the table).
    """
    model = load_model(path)
    try:
        check_decidable(model)
    except InvalidInputError as error:
        raise ModelFileError(str(path), error.message, **error.evidence) from None
    return model
