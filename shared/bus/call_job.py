"""One call a service works on: its first query, and the ones asked again.

A caller that has no answer after ``resend_after`` asks again with the
same call id (``CallerBudget.call``). If the first query is still queued
or running, the second joins it here: one piece of work, and its answer
goes to every query of the call. Refused ``service_busy`` instead (its
queue full of the very requests it was waiting for), the second query's
error was the caller's first answer, while the first query was still
worked on and its plan published: 11 of 12 callers were told busy for
plans the robot would play.
"""

from __future__ import annotations

from typing import Any

import zenoh

from shared.bus.deadline import Due
from shared.bus.route import Endpoint


class CallJob:
    """A call queued or running: its endpoint, key and every query of it.

    Not thread-safe: the service host guards ``add`` and ``close`` with its
    lock.

    Attributes:
        endpoint: The endpoint that answers it.
        key: Its full key, e.g. ``"armplan/plan"``.
        call: The caller's id for the call; ``None``: the query is its own
            call, and nothing joins it.
        arrived: When its first query arrived [s, monotonic]; None: not said.
    """

    def __init__(
        self,
        endpoint: Endpoint[Any, Any],
        key: str,
        query: zenoh.Query,
        due: Due | None,
        arrived: float | None = None,
    ) -> None:
        self.endpoint, self.key = endpoint, key
        self.arrived = arrived
        self.call = None if due is None else due.call
        self._queries = [query]
        self._dues = [due]
        self._closed = False

    @property
    def first(self) -> zenoh.Query:
        """The call's first query (the one whose request is worked on)."""
        return self._queries[0]

    def add(self, query: zenoh.Query, due: Due | None, same: bool = True) -> bool:
        """Answer ``query`` too, if it asks the same; ``False``: it does not.

        A query of this call with another request (a caller that reused its
        call id) is not answered with this one's answer; unless ``same`` is
        False: any request is answered with it (an urgent endpoint's, whose
        work was done as each query arrived, ``Endpoint.at_once``).
        """
        assert not self._closed, "a query joined a call already answered"
        if same and _body(query) != _body(self.first):
            return False
        self._queries.append(query)
        self._dues.append(due)
        return True

    def due(self) -> Due | None:
        """When the last of its callers stops waiting; ``None``: one never does."""
        if any(due is None for due in self._dues):
            return None
        return max((due for due in self._dues if due is not None), key=_at)

    def close(self) -> list[zenoh.Query]:
        """Take its queries to answer; nothing joins it after this."""
        self._closed = True
        return list(self._queries)


def _at(due: Due) -> float:
    return due.at


def _body(query: zenoh.Query) -> bytes:
    return b"" if query.payload is None else query.payload.to_bytes()
