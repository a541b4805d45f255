"""A warning for a ``--rotate-duration`` under a second.

Each part of a rotated recording stands alone (its header, metadata, robot
description, schemas and summary: ``size_floor``), and the recorder starts
a new one as soon as the duration has passed, flush or no flush. With
``--rotate-duration 0.01`` a lab got 73 files in 8 s and no word; at the
bridge's state rate that is a file for nearly every message. It is the
user's choice, so the recorder only warns, and records as asked.
"""

from __future__ import annotations

import logging

log = logging.getLogger("armplan.recorder")

#: The shortest sane ``--rotate-duration`` [s]: a part a second at most.
SANE_DURATION = 1.0
#: Seconds in an hour, for the warning's count of files.
HOUR = 3600.0


def duration_note(seconds: float) -> str | None:
    """The warning for a rotation duration below :data:`SANE_DURATION`, or ``None``.

    Args:
        seconds: The duration as given [s] (positive: checked before).
    """
    if seconds >= SANE_DURATION:
        return None
    return (
        f"recorder: --rotate-duration {seconds:g} starts a new file every "
        f"{seconds:g} s, up to {HOUR / seconds:.0f} files an hour, each with its own "
        f"header, schemas and summary; a sane duration is at least "
        f"{SANE_DURATION:g} s (recording as asked)"
    )


def warn_if_short(seconds: float | None) -> None:
    """Log :func:`duration_note` as a warning if there is one (none given: none)."""
    note = None if seconds is None else duration_note(seconds)
    if note is not None:
        log.warning("%s", note)
