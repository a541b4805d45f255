"""The caller's deadline inside a service: skip or stop work no one awaits.

Every query carries a :class:`~shared.messages.CallerBudget` (the caller's
time left [s], and when it was sent by the caller's wall clock) as its
attachment. The service host turns it into a deadline on its own monotonic
clock when the query arrives, less the time the query spent on its way
(:func:`deadline_of`): a query held up before it arrived (a paused process,
a congested link) has its caller's wait counted from the sending. A query
still queued past its deadline is dropped unserved; a handler runs inside
:func:`serving_until`, so that it can ask :func:`current_due` before doing
what only a waiting caller wants (the planner publishes a trajectory, which
a following robot plays, only if its caller still waits).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import NamedTuple

import zenoh
from pydantic import ValidationError

from shared.messages import CallerBudget
from shared.messages.caller_budget import MAX_BUDGET

#: Longest attachment read as a budget [bytes] (ours are about 20).
LONGEST = 256
#: An answer finished this close to its caller's deadline counts as too late
#: [s]: the deadline runs from the query's arrival, later than its sending,
#: and the answer must still travel back. With none, 1 in 10 plans whose
#: callers were told ``request_timeout`` was published within 2 ms of it.
REPLY_MARGIN = 0.05

_local = threading.local()


class Due(NamedTuple):
    """When a query's caller stops waiting.

    Attributes:
        at: The deadline [s, this process's monotonic clock].
        budget: The caller's time left when it sent the query [s].
        transit: Time from its sending to its arrival, by the two wall
            clocks [s], at least 0.
        call: The caller's id for the call, shared by a query and the one it
            asks again (``CallerBudget.call``); ``None``: not said.
        session: The caller's Zenoh session id (``CallerBudget.session``);
            ``None``: not said.
        again: Asked again only if the service never had the call
            (``CallerBudget.again``).
    """

    at: float
    budget: float
    transit: float = 0.0
    call: str | None = None
    session: str | None = None
    again: bool = False

    @property
    def passed(self) -> bool:
        """Whether the caller has stopped waiting."""
        return time.monotonic() > self.at

    @property
    def too_late(self) -> bool:
        """Whether an answer sent now may come after the caller stopped waiting.

        That is: within :data:`REPLY_MARGIN` of the deadline, or past it.
        """
        return time.monotonic() > self.at - REPLY_MARGIN


def budget_attachment(
    seconds: float,
    sent: float | None = None,
    call: str | None = None,
    session: str | None = None,
    again: bool = False,
) -> bytes:
    """The attachment of a query whose caller waits ``seconds`` [s] more.

    Clamped to a millisecond .. a day (``MAX_BUDGET``): a longer wait is
    told as a day. ``sent``: the sending's wall-clock time [s since the
    epoch], default now. ``call``: the caller's id for the call, the same on
    a query asked again (``CallerBudget.call``). ``session``: the caller's
    Zenoh session id (``CallerBudget.session``). ``again``: asked again
    only if the service never had the call (``CallerBudget.again``).
    """
    budget = min(max(seconds, 1e-3), MAX_BUDGET)
    when = time.time() if sent is None else sent
    told = CallerBudget(
        timeout=budget, sent=when, call=call, session=session, again=again
    )
    # said only when true: a service older than the field, which refuses
    # unknown fields, still reads every other query's budget
    return told.model_dump_json(exclude=None if again else {"again"}).encode()


def deadline_of(
    query: zenoh.Query, received: float, arrived: float | None = None
) -> Due | None:
    """When the caller of ``query`` stops waiting, if it said.

    Args:
        query: The query.
        received: When it arrived [s, monotonic clock].
        arrived: The same moment by the wall clock [s since the epoch];
            default now.

    Returns:
        ``received`` plus the caller's budget less the query's transit, or
        ``None`` for a query without a (valid) budget: it is served
        whenever its turn comes.
    """
    attachment = query.attachment
    if attachment is None:
        return None
    data = attachment.to_bytes()
    if len(data) > LONGEST:  # not ours; parsed on Zenoh's thread, so not read
        return None
    try:
        budget = CallerBudget.model_validate_json(data)
    except ValidationError:
        return None
    transit = 0.0
    if budget.sent is not None:
        now = time.time() if arrived is None else arrived
        transit = max(now - budget.sent, 0.0)
    at = received + budget.timeout - transit
    return Due(at, budget.timeout, transit, budget.call, budget.session, budget.again)


@contextmanager
def serving_until(due: Due | None) -> Iterator[None]:
    """Run the block as the handler of a query ``due`` then (``None``: never)."""
    before = getattr(_local, "due", None)
    _local.due = due
    try:
        yield
    finally:
        _local.due = before


def current_due() -> Due | None:
    """The deadline of the query this thread serves, if it has one."""
    due: Due | None = getattr(_local, "due", None)
    return due
