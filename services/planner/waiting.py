"""Who still waits for a plan: the callers of one request, first and repeats.

A plan asked for again under the same ``request_id`` is worked on once, on
the first caller's thread (``answer_once``), while the repeats wait for it.
The planner publishes a finished plan only if some caller still waits for
it (a following robot would otherwise move for no one), so it must know the
deadlines of all of them, not only the first's: a repeat sent because the
first call timed out still waits.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

from shared.bus.deadline import REPLY_MARGIN, Due


class Waiting:
    """The deadlines of the callers now waiting, per request id."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._ats: dict[str, list[float | None]] = {}

    @contextmanager
    def caller(self, key: str | None, due: Due | None) -> Iterator[None]:
        """Count a caller of ``key`` as waiting, for the duration of the block.

        ``due`` is when it stops waiting (``None``: it never does).
        """
        at = None if due is None else due.at
        if key is not None:
            with self._lock:
                self._ats.setdefault(key, []).append(at)
        try:
            yield
        finally:
            if key is not None:
                with self._lock:
                    ats = self._ats[key]
                    ats.remove(at)
                    if not ats:
                        del self._ats[key]

    def all_gone(self, key: str | None, due: Due | None) -> bool:
        """Whether every caller of ``key`` stops waiting before an answer.

        That is: each is past its deadline or within ``REPLY_MARGIN`` of it
        (an answer sent now may not reach it in time). Without a ``key``:
        whether the one caller, due by ``due``, does.
        """
        if key is None:
            return due is not None and due.too_late
        late = time.monotonic() + REPLY_MARGIN
        with self._lock:
            ats = list(self._ats.get(key, []))
        return bool(ats) and all(at is not None and late > at for at in ats)
