"""Which model the fit service starts with, and where it keeps the one it serves.

At start, in this order: the model file given (``--model FILE``; a bad
one, or one the decision cannot use, stops the service with
``ModelFileError``), else the model it served last (its state file in its
state directory, by default the demonstration directory; checked the same
way), else the shipped default. The state file belongs to the namespace:
``STATE_FILE`` for the default one, ``armplan-fit-model.<ns>.json`` (the
namespace's ``/`` as ``.``) for another, so two robots with their own
namespaces never serve or overwrite each other's model. Whenever the
served model changes (a fit, or a start from ``--model``), it is written
to the state file atomically, so a restarted fit service serves the same
model. Delete the state file to start from the shipped default again.
Each start logs which model it serves: where it came from and
``digest`` (the first 12 hex digits of the SHA-256 of its JSON).
"""

from __future__ import annotations

import hashlib
import logging
import tempfile
from pathlib import Path
from typing import NamedTuple

from services.fit.decidable import load_decidable
from services.fit.default import default_model, default_model_path
from services.fit.model_file import save_model
from shared.bus.config import DEFAULT_NAMESPACE
from shared.errors import InvalidInputError, ModelFileError
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


def state_file(state_dir: Path, namespace: str) -> Path:
    """The state file of ``namespace``'s fit service in ``state_dir``.

    ``STATE_FILE`` for the default namespace (as before namespaces had their
    own), else ``armplan-fit-model.lab.nao1.json`` for ``lab/nao1``: a ``.``
    is in no namespace chunk, so two namespaces never share a file.
    """
    if namespace == DEFAULT_NAMESPACE:
        return state_dir / STATE_FILE
    stem = STATE_FILE.removesuffix(".json")
    return state_dir / f"{stem}.{namespace.replace('/', '.')}.json"


def say_other_state(state: Path, namespace: str) -> None:
    """Log that the default namespace's state file beside ``state`` is not read.

    Before each namespace had its own state file, every fit service kept its
    model in ``STATE_FILE``: a robot of another namespace finds it there and
    is told how to serve it, rather than serving another robot's model.
    """
    shared = state.with_name(STATE_FILE)
    if shared == state or state.exists() or not shared.exists():
        return
    log.warning(
        "not reading %s: it is the state file of namespace %r; this fit "
        "service (namespace %r) keeps its model in %s (rename the file, or "
        "give --model %s, to serve that model)",
        shared,
        DEFAULT_NAMESPACE,
        namespace,
        state.name,
        shared,
    )


def check_state_dir(state_dir: Path, given: bool) -> None:
    """Make sure the served model can be kept in ``state_dir``, or say so.

    A folder that is missing or cannot be written in used to be found out
    at the first fit, in a log line, and the lab's model was lost at the
    next restart.

    Args:
        state_dir: Where the state file goes.
        given: Whether it was named (``--state-dir``) rather than the default.

    Raises:
        InvalidInputError: ``given`` and the folder is missing, no folder, or
            not writable. The default folder only gets a warning at start.
    """
    problem = _unwritable(state_dir)
    if problem is None:
        return
    if given:
        raise InvalidInputError(
            f"--state-dir {state_dir}: {problem}; the fit service keeps the "
            "model it serves there for a restart",
            field="state_dir",
            path=str(state_dir),
        )
    log.warning(
        "a fitted model will be served but not kept for a restart: %s: %s "
        "(give --state-dir DIR)",
        state_dir,
        problem,
    )


def _unwritable(folder: Path) -> str | None:
    """Why no file can be written in ``folder``, or ``None`` if one can."""
    if not folder.is_dir():
        return "no such folder" if not folder.exists() else "not a folder"
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".armplan-fit-probe-"):
            return None
    except OSError as error:
        return f"cannot write in it ({error.strerror})"


def start_model(model_file: str | None, state: Path | None) -> StartModel:
    """The model to start with (see the module's docstring).

    Args:
        model_file: The ``--model`` file, or ``None``.
        state: The state file, or ``None`` for none (nothing kept).

    Raises:
        ModelFileError: ``model_file``, or an existing state file, is not a
            valid motion model (missing, truncated, of another version...,
            or one the decision cannot use: ``load_decidable``); a bad
            state file is not passed over for the shipped default.
    """
    if model_file is not None:
        return StartModel(load_decidable(model_file), f"--model {model_file}", True)
    if state is not None and state.exists():
        try:
            return StartModel(load_decidable(state), f"state {state}")
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
