"""When the query a thread serves arrived: what came after it may concern it.

The service host notes each query's arrival on its own monotonic clock as
Zenoh hands it over (before anything else is done with it), and runs the
handler, and an urgent endpoint's ``at_once``, inside :func:`arrived_at`.
A handler asks :func:`current_arrival`: the bridge's ``bridge/execute``
takes the robot with it, so that an operator's ``bridge/stop`` that came
after the query arrived, while the query waited in the queue or was
checked, stops it too (nothing of it is sent).
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager

_local = threading.local()


@contextmanager
def arrived_at(at: float | None) -> Iterator[None]:
    """Run the block for a query that arrived at ``at`` [s, monotonic]."""
    before = getattr(_local, "at", None)
    _local.at = at
    try:
        yield
    finally:
        _local.at = before


def current_arrival() -> float | None:
    """When the query this thread serves arrived [s, monotonic]; None: not said."""
    at: float | None = getattr(_local, "at", None)
    return at
