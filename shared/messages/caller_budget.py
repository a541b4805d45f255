"""How long a caller will wait for its answer, sent along with each query."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import Message

#: Longest wait a caller may announce [s] (a day: any real timeout).
MAX_BUDGET = 86_400.0


class CallerBudget(Message):
    """The time a caller has left for its answer when it sends a query.

    A caller sends it as the Zenoh attachment of each query (JSON), never in
    the payload, so the request's JSON stays the same. The service counts
    from the moment it receives the query (clocks of two machines are never
    compared), so a request that waited in its queue past the budget is not
    worked on: no one is waiting for it.

    Attributes:
        timeout: Time left for the answer when the query was sent [s].
    """

    timeout: float = Field(gt=0.0, le=MAX_BUDGET)
