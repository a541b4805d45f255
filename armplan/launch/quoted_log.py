"""A start failure of a run that keeps no log: the log's own last words.

A child that exits while starting is reported "... exited with code 1 while
starting (see its log)". ``armplan bench`` starts the router and the
services for its run only and keeps no log folder, so there is no log to
see. Their output goes to a temporary file instead; :func:`quoting_log`
replaces the pointer with what that output said last (the router: "cannot
listen on tcp/127.0.0.1:7447 (... Address already in use ...)").
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from shared.errors import ArmplanError, error_from_wire

#: What a start failure says about its output (``Launcher``, ``RobotStack``).
SEE_LOG = "(see its log)"
#: The same when the output went to this process's stderr (``armplan up``):
#: there is no log file, the output is on the terminal.
SEE_ABOVE = "(see its output above)"
#: The level word of an error line of armplan's logging.
ERROR = " ERROR "
#: Terminal colour codes (Zenoh's own log lines carry them).
COLOURS = re.compile(r"\x1b\[[0-9;]*m")


def log_pointer(log: IO[str] | int | None) -> str:
    """Where a start failure points for a child's output sent to ``log``.

    :data:`SEE_ABOVE` for ``None`` (this process's stderr), else :data:`SEE_LOG`.
    """
    return SEE_ABOVE if log is None else SEE_LOG


def last_words(path: Path) -> str:
    """The last error line of the log at ``path``, else its last line; ``""`` if none.

    Of an armplan error line only the message is kept (the part after
    ``ERROR``); colour codes are removed.
    """
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return ""
    lines = [COLOURS.sub("", line).strip() for line in text.splitlines()]
    lines = [line for line in lines if line]
    errors = [line for line in lines if ERROR in line]
    if errors:
        return errors[-1].split(ERROR, 1)[1].strip()
    return lines[-1] if lines else ""


@contextlib.contextmanager
def quoting_log(path: Path) -> Iterator[None]:
    """A start failure inside that says :data:`SEE_LOG` quotes ``path``'s last words.

    The error keeps its kind and evidence (plus ``output``, the words
    quoted); only its message changes, e.g. "... exited with code 1 while
    starting; its output ended: router: ... Address already in use ...".
    """
    try:
        yield
    except ArmplanError as error:
        if SEE_LOG not in error.message:
            raise
        said = last_words(path)
        quoted = f"; its output ended: {said}" if said else "; it printed nothing"

        def quote(value: object) -> object:
            return (
                value.replace(f" {SEE_LOG}", quoted)
                if isinstance(value, str)
                else value
            )

        evidence = {key: quote(value) for key, value in error.evidence.items()}
        wire = {
            "kind": error.kind,
            "message": quote(error.message),
            "evidence": {**evidence, "output": said},
        }
        raise error_from_wire(wire) from None
