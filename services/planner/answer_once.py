"""Answer a repeated request once: the planner's guard against asking twice.

A caller that gets no answer in time may ask again with the same request id
(``PlanRequest.request_id``). :class:`AnswerOnce` runs the work for the first
request with an id; a repeat arriving while it runs waits for its answer, and
one arriving later gets the kept answer, so a plan is computed and published
once however often it is asked for. A failed attempt is forgotten once its
waiters have its error, so asking again then retries.

What is kept per id: a SHA-256 digest of the request (to tell a repeat from
an id reused for another request), and the answer. An id is forgotten
``HOLD`` seconds after it first came (a caller repeats within its own
timeout, seconds), or when more than ``KEEP`` ids came since. The answers
kept weigh at most a ``budget`` (the planner: ``KEPT_SAMPLES`` trajectory
samples, so a few long trajectories do not hold gigabytes for a minute):
past it the oldest answers go first (the newest is always kept), but their
ids stay, so a repeat is still known as one: it gets ``again()``'s answer
(the planner plans again without publishing: the robot moves once), or an
error if there is no ``again``. Ids are cheap (about 200 bytes each), so
``KEEP`` is large: at 170 plans a second, 256 ids once lasted under 3 s
and a caller's repeat after its 5 s timeout was planned and played twice.
"""

from __future__ import annotations

import hashlib
import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from concurrent.futures import Future
from typing import Generic, NamedTuple, TypeVar

from shared.errors import InvalidInputError

Req = TypeVar("Req")
Rep = TypeVar("Rep")

#: Most ids kept for repeats that arrive after the first one was answered.
KEEP = 65_536
#: Time after which an id is forgotten [s].
HOLD = 60.0


def one(_: object) -> int:
    """Every answer weighs 1: the budget then counts answers."""
    return 1


class _Seen(NamedTuple, Generic[Rep]):
    digest: bytes  # SHA-256 of the request's fingerprint
    since: float  # when the id first came [s], monotonic clock
    future: Future[Rep] | None  # None: answered, the answer no longer kept


class AnswerOnce(Generic[Req, Rep]):
    """The answers to the ids of the last ``hold`` seconds (``keep`` at most).

    Args:
        fingerprint: The request as text or bytes that differ whenever two
            requests do (the planner: the request's JSON); ``repr`` by default.
        keep: How many ids to remember at most.
        hold: How long an id is remembered [s].
        clock: The time [s] (monotonic); for tests.
        weight: What an answer weighs (the planner: its samples); 1 by default.
        budget: The most the kept answers may weigh together; the newest
            answer is kept whatever it weighs. No limit by default.
    """

    def __init__(
        self,
        fingerprint: Callable[[Req], str | bytes] = repr,
        keep: int = KEEP,
        hold: float = HOLD,
        clock: Callable[[], float] = time.monotonic,
        weight: Callable[[Rep], int] = one,
        budget: float = float("inf"),
    ) -> None:
        self._fingerprint = fingerprint
        self._keep, self._hold, self._clock = keep, hold, clock
        self._weight, self._budget = weight, budget
        self._lock = threading.Lock()
        self._seen: OrderedDict[str, _Seen[Rep]] = OrderedDict()
        self._kept: OrderedDict[str, int] = OrderedDict()  # answered id -> weight
        self._weighed = 0  # the kept answers' weight together

    def weighed(self) -> int:
        """What the answers kept now weigh together."""
        with self._lock:
            self._forget(self._clock())
            return self._weighed

    def __len__(self) -> int:
        """How many ids are remembered now."""
        with self._lock:
            self._forget(self._clock())
            return len(self._seen)

    def answer(
        self,
        key: str | None,
        request: Req,
        work: Callable[[], Rep],
        again: Callable[[], Rep] | None = None,
    ) -> Rep:
        """``work()``'s answer, run once per ``key`` (every time if ``key`` is None).

        Args:
            key: The request's id.
            request: The request (its fingerprint tells repeats apart).
            work: Makes the answer, with its effects (the planner publishes).
            again: Makes the same answer without the effects, for a repeat
                whose answer is no longer kept.

        Raises:
            InvalidInputError: ``key`` was used before for another request,
                or (without ``again``) its answer is no longer kept.
            Whatever ``work`` raises (also to the repeats waiting for it).
        """
        if key is None:
            return work()
        digest = _digest(self._fingerprint(request))
        with self._lock:
            now = self._clock()
            self._forget(now)
            seen = self._seen.get(key)
            if seen is None:
                future: Future[Rep] = Future()
                self._seen[key] = _Seen(digest, now, future)
                self._forget(now)
        if seen is not None:
            return _repeat(key, digest, seen, again)
        try:
            result = work()
        except BaseException as error:
            with self._lock:
                if self._owns(key, future):
                    self._drop(key)
            future.set_exception(error)
            raise
        future.set_result(result)
        self._weigh(key, future, result)
        return result

    def _owns(self, key: str, future: Future[Rep]) -> bool:
        """Whether ``key`` is still ``future``'s entry (held lock).

        Not if it was forgotten, or forgotten and asked for anew, while the
        work ran.
        """
        seen = self._seen.get(key)
        return seen is not None and seen.future is future

    def _weigh(self, key: str, future: Future[Rep], result: Rep) -> None:
        """Count ``key``'s answer in the budget; drop the oldest answers past it."""
        weight = self._weight(result)
        with self._lock:
            if not self._owns(key, future):
                return
            self._kept[key] = weight
            self._weighed += weight
            while self._weighed > self._budget:
                old = next(iter(self._kept))
                if old == key:  # the newest stays
                    return
                self._weighed -= self._kept.pop(old)
                self._seen[old] = self._seen[old]._replace(future=None)

    def _forget(self, now: float) -> None:
        """Drop the oldest ids beyond ``keep`` and those older than ``hold``."""
        while self._seen:
            key, oldest = next(iter(self._seen.items()))
            if len(self._seen) <= self._keep and now - oldest.since <= self._hold:
                return
            self._drop(key)

    def _drop(self, key: str) -> None:
        """Forget ``key`` and its answer (held lock)."""
        self._seen.pop(key, None)
        if key in self._kept:
            self._weighed -= self._kept.pop(key)


def _digest(fingerprint: str | bytes) -> bytes:
    data = fingerprint.encode() if isinstance(fingerprint, str) else fingerprint
    return hashlib.sha256(data).digest()


def _repeat(
    key: str, digest: bytes, seen: _Seen[Rep], again: Callable[[], Rep] | None
) -> Rep:
    if digest != seen.digest:
        raise InvalidInputError(
            f"request_id {key!r} was used for another request",
            field="request_id",
        )
    if seen.future is not None:
        return seen.future.result()
    if again is None:
        raise InvalidInputError(
            f"request_id {key!r} was answered already and its answer is no "
            "longer kept: ask with a new request_id",
            field="request_id",
        )
    return again()
