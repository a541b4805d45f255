"""Who still waits for a plan: the callers of one request, first and repeats.

A plan asked for again under the same ``request_id`` is worked on once, on
the first caller's thread (``answer_once``), while the repeats wait for it.
The planner publishes a finished plan only if some caller still waits for
it (a following robot would otherwise move for no one), so it must know the
deadlines of all of them, not only the first's: a repeat sent because the
first call timed out still waits. A caller whose session has ended (its
``armplan plan`` interrupted with Ctrl-C, or killed) waits no more, whatever
its deadline (``shared.bus.gone_callers``).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from shared.bus.deadline import Due

#: Whether the session of this id (``Due.session``) has ended; ``None``: not said.
Ended = Callable[[str | None], bool]


def _never(_session: str | None) -> bool:
    return False


class Waiting:
    """The callers now waiting, per request id: their deadlines and sessions."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._dues: dict[str, list[Due | None]] = {}

    @contextmanager
    def caller(self, key: str | None, due: Due | None) -> Iterator[None]:
        """Count a caller of ``key`` as waiting, for the duration of the block.

        ``due`` is when it stops waiting and its session (``None``: it never
        stops, and its session is not known).
        """
        if key is not None:
            with self._lock:
                self._dues.setdefault(key, []).append(due)
        try:
            yield
        finally:
            if key is not None:
                with self._lock:
                    dues = self._dues[key]
                    dues.remove(due)
                    if not dues:
                        del self._dues[key]

    def all_gone(self, key: str | None, due: Due | None, ended: Ended = _never) -> bool:
        """Whether every caller of ``key`` is gone before an answer.

        That is: each is past its deadline or within
        :data:`~shared.bus.deadline.REPLY_MARGIN` of it
        (an answer sent now may not reach it in time), or its session has
        ended (``ended``: its process was interrupted or killed). Without a
        ``key``: whether the one caller, due by ``due``, is.
        """
        if key is None:
            return due is not None and _gone(due, ended)
        with self._lock:
            dues = list(self._dues.get(key, []))
        return bool(dues) and all(d is not None and _gone(d, ended) for d in dues)

    def all_ended(self, key: str | None, due: Due | None, ended: Ended) -> bool:
        """Whether every caller of ``key`` has ended its session (``ended``).

        Its process was interrupted or killed: it can neither take an answer
        nor ask again, whatever its deadline. A caller past its deadline
        whose session runs may still ask again (:meth:`all_gone` counts it
        gone). Without a ``key``: whether the one caller, due by ``due``, has.
        """
        if key is None:
            return due is not None and ended(due.session)
        with self._lock:
            dues = list(self._dues.get(key, []))
        return bool(dues) and all(d is not None and ended(d.session) for d in dues)


def _gone(due: Due, ended: Ended) -> bool:
    """Whether the caller due by ``due`` stops waiting before an answer."""
    return due.too_late or ended(due.session)
