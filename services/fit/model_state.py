"""Which model the fit service starts with, and where it keeps the one it serves.

At start, in this order: the model file given (``--model FILE``; a bad
one stops the service with ``ModelFileError``), else the model it served
last (its state file, ``STATE_FILE`` in its state directory, by default
the demonstration directory), else the shipped default. Whenever the
served model changes (a fit, or a start from ``--model``), it is written
to the state file atomically, so a restarted fit service serves the same
model. Delete the state file to start from the shipped default again.
Each start logs which model it serves: where it came from and
``digest`` (the first 12 hex digits of the SHA-256 of its JSON).
"""

from __future__ import annotations

import hashlib
import logging
from pathlib import Path
from typing import NamedTuple

from services.fit.default import default_model, default_model_path
from services.fit.model_file import load_model, save_model
from shared.errors import ModelFileError
from shared.messages import MotionModel

log = logging.getLogger("armplan.fit")

#: The state file's name inside the fit service's state directory.
STATE_FILE = "armplan-fit-model.json"


class StartModel(NamedTuple):
    """The model a fit service starts with.

    Attributes:
        model: The model.
        source: Where it came from: ``"--model <file>"``, ``"state <file>"``
            or ``"shipped default <file>"``.
        given: Whether it came from ``--model`` (it is then kept in the state
            file at start; the shipped default is not written there).
    """

    model: MotionModel
    source: str
    given: bool = False


def digest(model: MotionModel) -> str:
    """A short content hash of ``model``: 12 hex digits of its JSON's SHA-256."""
    return hashlib.sha256(model.model_dump_json().encode()).hexdigest()[:12]


def state_file(state_dir: Path) -> Path:
    """The state file in ``state_dir``."""
    return state_dir / STATE_FILE


def start_model(model_file: str | None, state: Path | None) -> StartModel:
    """The model to start with (see the module's docstring).

    Args:
        model_file: The ``--model`` file, or ``None``.
        state: The state file, or ``None`` for none (nothing kept).

    Raises:
        ModelFileError: ``model_file``, or an existing state file, is not a
            valid motion model (missing, truncated, of another version...);
            a bad state file is not passed over for the shipped default.
    """
    if model_file is not None:
        return StartModel(load_model(model_file), f"--model {model_file}", True)
    if state is not None and state.exists():
        try:
            return StartModel(load_model(state), f"state {state}")
        except ModelFileError as exc:
            raise ModelFileError(
                str(state),
                f"{exc.reason}; it holds the model the fit service served "
                "last: delete it to start from the shipped default, or give "
                "--model FILE",
            ) from None
    return StartModel(default_model(), f"shipped default {default_model_path()}")


def keep(model: MotionModel, state: Path | None) -> None:
    """Write ``model`` to the state file (atomically); a failure is logged.

    The model is served all the same; only a restart would lose it.
    """
    if state is None:
        return
    try:
        save_model(model, state)
    except ModelFileError as exc:
        log.warning(
            "model %s is served but not kept for a restart: %s",
            digest(model),
            exc.message,
        )
