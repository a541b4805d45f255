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
    from the moment it receives the query, less the time the query took to
    get there by the two wall clocks (``sent``; a negative transit, a caller
    whose clock is ahead, counts as none), so a request that waited on its
    way or in its queue past the budget is not worked on: no one is waiting
    for it. Across machines this needs clocks kept in step (NTP): a service
    whose clock runs ahead of its callers' by more than their budgets drops
    every request, and says so in its log.

    Attributes:
        timeout: Time left for the answer when the query was sent [s].
        sent: When it was sent, by the caller's wall clock [s since the Unix
            epoch]; ``None`` (a caller that does not say): counted from
            receipt alone.
        call: The caller's id for the call, the same on a query and on the
            query it asks again (``caller.answered``); the service answers
            both from one piece of work, never ``service_busy`` to the second
            while the first waits or runs. ``None``: a call asked once.
        session: The caller's Zenoh session id (hex), whose caller token
            (``<ns>/caller/<session>``) goes when the caller's session ends:
            a service may then drop what only that caller wanted (the
            planner does not publish its plan). ``None``: not said.
        again: The query asks the call again only on the guess that its
            first query reached no one (it ended at once without a reply:
            ``caller.answered``, a call that is not repeatable); the service
            refuses it if it has had a query of the call, so that a wrong
            guess (a reply lost, or refused by a router) never does the
            work twice.
    """

    timeout: float = Field(gt=0.0, le=MAX_BUDGET)
    sent: float | None = Field(default=None, gt=0.0)
    call: str | None = Field(default=None, pattern=r"^[A-Za-z0-9_.-]{1,64}$")
    session: str | None = Field(default=None, pattern=r"^[0-9a-f]{1,32}$")
    again: bool = False
