"""Client sessions a process left open are closed before it waits for its threads.

A subscriber with a Python callback (every :class:`~shared.bus.Bus` watches
liveliness tokens so) gets a reader thread from zenoh-python, not a daemon,
that ends only when its session closes; and Python waits for every such
thread before it exits. A session left open so hung its process at exit for
ever: a script that opened a ``Bus`` and ended without closing it ran until
killed. So did ``armplan demo`` sent SIGTERM just as it connected to plan
(1 run in 40 here): the signal's exception came out after the session had
opened and before the ``with`` block held it, so no one closed it; a demo
in one CI run did not exit within 90 s of SIGTERM, likely so.

:func:`held` records a session as it opens, before anything is declared on
it; :func:`close` closes one and forgets it. What is still held when the
interpreter exits is closed by threading's own exit hook, which runs before
the threads are joined (``concurrent.futures`` stops its workers the same
way), and the process ends.
"""

from __future__ import annotations

import contextlib
import threading

import zenoh

_held: set[zenoh.Session] = set()
_lock = threading.Lock()


def held(session: zenoh.Session) -> zenoh.Session:
    """Record ``session`` as open; returns it."""
    with _lock:
        _held.add(session)
    return session


def close(session: zenoh.Session) -> None:
    """Close ``session`` and forget it."""
    session.close()  # type: ignore[no-untyped-call]
    with _lock:
        _held.discard(session)


def still_open() -> int:
    """How many sessions are held now."""
    with _lock:
        return len(_held)


def close_left_open() -> None:
    """Close every session still held (at exit: no one else will)."""
    with _lock:
        left = list(_held)
        _held.clear()
    for session in left:
        with contextlib.suppress(zenoh.ZError):  # closed meanwhile
            session.close()  # type: ignore[no-untyped-call]


threading._register_atexit(close_left_open)  # type: ignore[attr-defined]
