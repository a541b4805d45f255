"""Answer a repeated request once: the planner's guard against asking twice.

A caller that gets no answer in time may ask again with the same request id
(``PlanRequest.request_id``). :class:`AnswerOnce` runs the work for the first
request with an id; a repeat arriving while it runs waits for its answer, and
one arriving later gets the kept answer, so a plan is computed and published
once however often it is asked for. A failed attempt is forgotten once its
waiters have its error, so asking again then retries.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable
from concurrent.futures import Future
from typing import Generic, TypeVar

from shared.errors import InvalidInputError

Req = TypeVar("Req")
Rep = TypeVar("Rep")

#: Answers kept for repeats that arrive after the first one was answered.
KEEP = 256


class AnswerOnce(Generic[Req, Rep]):
    """The answers of the last ``keep`` requests, by request id.

    Args:
        keep: How many answered ids to remember.
    """

    def __init__(self, keep: int = KEEP) -> None:
        self._keep = keep
        self._lock = threading.Lock()
        self._seen: OrderedDict[str, tuple[Req, Future[Rep]]] = OrderedDict()

    def answer(self, key: str | None, request: Req, work: Callable[[], Rep]) -> Rep:
        """``work()``'s answer, run once per ``key`` (every time if ``key`` is None).

        Raises:
            InvalidInputError: ``key`` was used before for another request.
            Whatever ``work`` raises (also to the repeats waiting for it).
        """
        if key is None:
            return work()
        with self._lock:
            seen = self._seen.get(key)
            if seen is None:
                future: Future[Rep] = Future()
                self._seen[key] = (request, future)
                while len(self._seen) > self._keep:
                    self._seen.popitem(last=False)
        if seen is not None:
            return self._repeat(key, request, *seen)
        try:
            result = work()
        except BaseException as error:
            with self._lock:
                self._seen.pop(key, None)
            future.set_exception(error)
            raise
        future.set_result(result)
        return result

    @staticmethod
    def _repeat(key: str, request: Req, first: Req, future: Future[Rep]) -> Rep:
        if request != first:
            raise InvalidInputError(
                f"request_id {key!r} was used for another request",
                field="request_id",
            )
        return future.result()
