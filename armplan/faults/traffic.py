"""Client traffic: threads sending requests over one bus, each one accounted for.

A :class:`Traffic` is a pool of client threads on one :class:`Bus`. Calls
go out in batches (:meth:`Traffic.send`); a scenario injects its fault
between or during batches and then collects every call's
:class:`~armplan.faults.outcome.Result`. A call whose thread never returns
(a hang) is counted as lost, not waited for forever.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Sequence
from concurrent.futures import Future, ThreadPoolExecutor, wait

from armplan.faults.outcome import SLACK, Call, Outcome, Result, send
from shared.bus import Bus
from shared.lifecycle import Closes

#: Pause between checks while waiting for calls to finish [s].
POLL = 0.02


def cycle(calls: Sequence[Call], count: int) -> list[Call]:
    """``count`` calls taken in turn from ``calls``."""
    return list(itertools.islice(itertools.cycle(calls), count))


class Traffic(Closes):
    """Client threads sending calls and classifying how each ended.

    Attributes:
        bus: The client session every thread shares.
        concurrency: Calls in flight at most.
        timeout: Each call's timeout [s].
    """

    def __init__(self, bus: Bus, concurrency: int, timeout: float) -> None:
        self.bus = bus
        self.concurrency = concurrency
        self.timeout = timeout
        self._pool = ThreadPoolExecutor(concurrency, thread_name_prefix="client")

    def send(self, calls: Sequence[Call]) -> list[Future[Result]]:
        """Queue ``calls``; they go out as threads come free."""
        return [self._pool.submit(send, self.bus, c, self.timeout) for c in calls]

    def wait_done(self, futures: Sequence[Future[Result]], count: int) -> None:
        """Wait until at least ``count`` of ``futures`` have finished."""
        while sum(f.done() for f in futures) < min(count, len(futures)):
            time.sleep(POLL)

    def results(self, futures: Sequence[Future[Result]]) -> list[Result]:
        """Every call's result; calls still running after their bound are lost.

        The bound is the time the batch needs if every call took its whole
        timeout: ``ceil(n / concurrency) * (timeout + SLACK)`` [s].
        """
        rounds = -(-len(futures) // self.concurrency)
        wait(futures, timeout=rounds * (self.timeout + SLACK))
        hung = Result("", Outcome.LOST, "hung", "", "the call never returned")
        return [f.result() if f.done() else hung for f in futures]

    def run(self, calls: Sequence[Call]) -> list[Result]:
        """Send ``calls`` and return their results."""
        return self.results(self.send(calls))

    def close(self) -> None:
        """Stop the threads (calls already sent end by their own timeout)."""
        self._pool.shutdown(wait=False, cancel_futures=True)
