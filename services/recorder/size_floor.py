"""A warning for a ``--rotate-size`` below what a part weighs on its own.

Each part of a rotated recording stands alone: MCAP header, the recording's
metadata, the robot description (with the Foxglove channels), then the
schema and channel of each topic before its first message, and a summary
on closing. Measured with a real recorder (default channels and schemas,
no motion model served), the closed parts weigh:

==========================  =====================  ===============
part                        Foxglove channels      ``--no-foxglove``
==========================  =====================  ===============
empty                       8690 bytes             684 bytes
one robot state             14.7 kB                2.3 kB
one planned trajectory      57 kB                  14.6 kB
==========================  =====================  ===============

A part is closed before the next message once it has reached the size, so
with ``--rotate-size 1k`` every message (and what it derives) is a file of
its own: thousands of files an hour at the bridge's state rate. It is the
user's choice, so the recorder only warns, and records as asked.
"""

from __future__ import annotations

import logging

from shared.text.counted import counted

log = logging.getLogger("armplan.recorder")

#: What an empty part weighs, closed [bytes], by whether it has the
#: Foxglove channels (measured: see the module's docstring).
EMPTY_PART = {True: 8690, False: 684}
#: The smallest sane ``--rotate-size`` [bytes], by the same: over 100 empty
#: parts, so a part's own weight is under 1 % of it.
SANE_SIZE = {True: 1024**2, False: 128 * 1024}
#: How :data:`SANE_SIZE` is given on the command line.
SANE_TEXT = {True: "1M", False: "128k"}


def size_note(given: str, max_bytes: int, foxglove: bool) -> str | None:
    """The warning for a rotation size below :data:`SANE_SIZE`, or ``None``.

    Args:
        given: The size as given, e.g. ``"1k"``.
        max_bytes: The size it reads as [bytes].
        foxglove: Whether the parts have the Foxglove channels.
    """
    if max_bytes >= SANE_SIZE[foxglove]:
        return None
    channels = "with the Foxglove channels" if foxglove else "with --no-foxglove"
    return (
        f"recorder: --rotate-size {given} ({counted(max_bytes, 'byte')}) is less "
        "than a part "
        f"needs: an empty part already weighs {EMPTY_PART[foxglove]} bytes "
        f"{channels}, more with its first messages' schemas, so nearly every "
        f"message will start a new file; a sane size is at least "
        f"{SANE_TEXT[foxglove]} (recording as asked)"
    )


def warn_if_small(given: str | None, max_bytes: int | None, foxglove: bool) -> None:
    """Log :func:`size_note` as a warning if there is one (no size: none)."""
    if given is None or max_bytes is None:
        return
    note = size_note(given, max_bytes, foxglove)
    if note is not None:
        log.warning("%s", note)
