"""Serve in-process functions over Zenoh: the thin wrapper of every service.

A :class:`ServiceHost` declares one queryable per endpoint under the
namespace, answers each query on a small pool of worker threads (so a slow
request never blocks Zenoh's own threads, and a handler may itself call other
services), and declares the liveliness token ``<ns>/alive/<service>`` once it
is ready. Every query is answered: a reply, or a ``reply_err`` carrying an
``ErrorReply`` (see ``codec.answer``); a full queue answers ``service_busy``,
except to a query its caller asked again (the same call id in its
attachment) while the first is still queued or running: that one joins the
first (``call_job``), so one piece of work answers both, and ``service_busy``
always means the request was not worked on.
An endpoint with ``own_worker`` has a queue and a worker of its own: its
queries are never queued behind the other endpoints' (a ``bridge/stop``
is answered while every worker plays or waits on ``bridge/execute``).
An *urgent* endpoint (``Endpoint.at_once``, the bridge's stop) has its
``at_once`` run on Zenoh's thread as each query arrives, before anything
else (no parsing, no queue, no deadline can keep it from running); its own
worker then answers: a query that comes while another is queued joins it
(one answer for both, whatever each asked), so its queue never fills, and
it is never dropped for its caller's deadline (a caller whose clock is
behind would lose an answer that costs little), nor refused for its size
(its payload is then read as empty: it was acted on all the same).
Each query's arrival (monotonic, noted as Zenoh hands it over) is told to
its handler and ``at_once`` (``shared.bus.arrival``). Once :meth:`stop`
has begun, a query is answered at once with ``service_unavailable``
(after an urgent endpoint's ``at_once`` has run): no worker is left to
answer it from a queue.
A reply's Zenoh attachment is a ``ServiceTiming``: where the request's time
went inside the service. A query's attachment is its caller's budget
(``shared.bus.deadline``): a query still queued when its caller has stopped
waiting is dropped unserved (not an urgent endpoint's), so a flood of
abandoned requests does not delay the next caller.
A query that says it is asked only if the service never had its call
(``CallerBudget.again``: a caller's guess that its first query reached no
one) is refused ``service_unavailable`` if a query of that call came
before (the last :data:`REMEMBERED` calls): a reply lost on its way never
makes a robot move twice.
"""

from __future__ import annotations

import contextlib
import logging
import queue
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from typing import Any

import zenoh

from shared.bus.arrival import arrived_at
from shared.bus.bus import Bus
from shared.bus.call_job import CallJob
from shared.bus.codec import Answer, answer, reply_error
from shared.bus.deadline import Due, deadline_of, serving_until
from shared.bus.keys import alive_key, check_name
from shared.bus.route import Endpoint
from shared.errors import ArmplanError, ServiceBusyError, ServiceUnavailableError
from shared.lifecycle import StartStop

log = logging.getLogger("armplan.bus")
#: Longest wait for a worker to finish its request when stopping [s].
STOP_GRACE = 2.0
#: Time a reply is given to leave before the stop goes on [s]: the session
#: closed right after a reply could drop it unsent (a bridge's report of a
#: trajectory it watched to its end as it stopped: its caller was told "no
#: queryable answered", 3 times in 3 on a loaded machine).
REPLY_FLUSH = 0.3
#: Calls remembered as had, for a query asked again only if its call was
#: not (``CallerBudget.again``); the oldest are forgotten first.
REMEMBERED = 4096


class ServiceHost(StartStop):
    """One service on the bus: its endpoints, workers and liveliness token.

    Args:
        bus: The bus it serves on.
        name: The service's name, e.g. ``"ik"``.
        endpoints: The routes it answers and their handlers.
        ready: Run once its queryables and token are declared, e.g. to
            publish a start state; ``None``: nothing.

    Attributes:
        name: The service's name, e.g. ``"ik"``.
        keys: The full key of each endpoint, e.g. ``["armplan/ik/solve"]``.
    """

    def __init__(
        self,
        bus: Bus,
        name: str,
        endpoints: Sequence[Endpoint[Any, Any]],
        ready: Callable[[], None] | None = None,
    ) -> None:
        self.name = check_name(name)
        self.keys = [e.route.key(bus.config.namespace) for e in endpoints]
        self._bus = bus
        self._endpoints = list(endpoints)
        self._ready = ready
        # the shared queue ("") and one per endpoint with its own worker (its key)
        self._lanes: dict[str, queue.Queue[CallJob | None]] = {
            lane: queue.Queue(bus.config.queue_limit)
            for lane in (
                "",
                *(_lane(e, k) for e, k in zip(endpoints, self.keys, strict=True)),
            )
        }
        for endpoint, key in zip(endpoints, self.keys, strict=True):
            if endpoint.urgent:  # never full: at most one job waits in it
                self._lanes[key] = queue.Queue()
        self._waiting: dict[str, CallJob] = {}  # an urgent key's job not yet begun
        self._lock = threading.Lock()  # guards _calls and the jobs in it
        self._calls: dict[tuple[str, str], CallJob] = {}  # queued or running
        self._had: OrderedDict[tuple[str, str], None] = OrderedDict()  # (key, call)
        self._workers: list[tuple[threading.Thread, queue.Queue[CallJob | None]]] = []
        self._queryables: list[zenoh.Queryable[None]] = []
        self._token: zenoh.LivelinessToken | None = None
        self._last_answer = -REPLY_FLUSH  # [s, monotonic]: none yet
        self._stopping = False  # set by stop(): nothing more is queued

    def start(self) -> ServiceHost:
        """Start workers, declare queryables, announce liveliness, run ``ready``."""
        self._stopping = False
        for i in range(self._bus.config.workers):
            self._start_worker(self._lanes[""], f"{self.name}-worker-{i}")
        for lane, jobs in self._lanes.items():
            if lane:
                self._start_worker(jobs, f"{self.name}-{lane.rsplit('/', 1)[-1]}")
        for endpoint, key in zip(self._endpoints, self.keys, strict=True):
            self._queryables.append(self._declare(endpoint, key))
        token_key = alive_key(self._bus.config.namespace, self.name)
        self._token = self._bus.session.liveliness().declare_token(token_key)
        log.info("service %s ready on %s", self.name, ", ".join(self.keys))
        if self._ready is not None:
            self._ready()
        return self

    def _start_worker(self, jobs: queue.Queue[CallJob | None], name: str) -> None:
        worker = threading.Thread(
            target=self._work, args=(jobs,), name=name, daemon=True
        )
        worker.start()
        self._workers.append((worker, jobs))

    def _declare(self, endpoint: Endpoint[Any, Any], key: str) -> zenoh.Queryable[None]:
        jobs = self._lanes[_lane(endpoint, key)]

        def enqueue(query: zenoh.Query) -> None:  # on Zenoh's thread: no waiting
            arrived = time.monotonic()
            if endpoint.at_once is not None:
                self._at_once(endpoint.at_once, key, query, arrived)
            admitted = self._admit(endpoint, key, query, jobs, arrived)
            if admitted is None:  # stopping: no worker will read a queue
                what = "acted on as it arrived, but " if endpoint.urgent else ""
                self._refuse(
                    query,
                    ServiceUnavailableError(
                        self.name,
                        key=key,
                        reason=f"{what}the service is stopping",
                    ),
                )
            elif admitted is _HAD:
                had = ServiceUnavailableError(
                    self.name,
                    key=key,
                    reason="it had this call's first query already, whose answer "
                    "was lost on its way (not done twice)",
                )
                self._refuse(query, had)
            elif not admitted:
                busy = ServiceBusyError(self.name, key=key, queued=jobs.qsize())
                self._refuse(query, busy)

        return self._bus.session.declare_queryable(key, enqueue)

    def _refuse(self, query: zenoh.Query, error: ArmplanError) -> None:
        """Answer ``query`` with ``error`` at once (on Zenoh's thread)."""
        with query, contextlib.suppress(zenoh.ZError):  # caller gone
            query.reply_err(
                reply_error(error), encoding=zenoh.Encoding.APPLICATION_JSON
            )
        self._last_answer = time.monotonic()  # see REPLY_FLUSH

    def _at_once(
        self,
        at_once: Callable[[bytes], None],
        key: str,
        query: zenoh.Query,
        arrived: float,
    ) -> None:
        """Run an urgent endpoint's ``at_once`` on ``query``'s raw payload.

        Inside :func:`~shared.bus.arrival.arrived_at` its arrival.
        """
        try:
            payload = query.payload
            size = 0 if payload is None else len(payload)
            data = (
                b""
                if payload is None or size > self._bus.config.max_payload
                else payload.to_bytes()
            )
            with arrived_at(arrived):
                at_once(data)
        except Exception:  # the query is still queued and answered
            log.exception("%s: failed to act on a query as it arrived", key)

    def _admit(
        self,
        endpoint: Endpoint[Any, Any],
        key: str,
        query: zenoh.Query,
        jobs: queue.Queue[CallJob | None],
        arrived: float,
    ) -> bool | object | None:
        """Queue ``query``, or join it to its call's first query; ``False``: full.

        A query asked again (its call id is that of a query queued or
        running) takes no place in the queue: refused busy, its error would
        be its caller's answer while the first query was still worked on.
        ``None``: the host is stopping (:meth:`stop`), nothing is queued.
        ``_HAD``: the query is asked only if its call is new
        (``Due.again``), and a query of it came before, now answered.
        """
        due = deadline_of(query, arrived)
        call = None if due is None else due.call
        if endpoint.urgent:
            return self._admit_urgent(endpoint, key, query, due, jobs, arrived)
        with self._lock:
            if self._stopping:
                return None
            job = None if call is None else self._calls.get((key, call))
            if job is not None and job.add(query, due):
                return True
            if due is not None and due.again and (key, call) in self._had:
                return _HAD
            job = CallJob(endpoint, key, query, due, arrived)
            try:
                jobs.put_nowait(job)
            except queue.Full:
                return False
            if call is not None and (key, call) not in self._calls:
                self._calls[(key, call)] = job
                self._had[(key, call)] = None
                while len(self._had) > REMEMBERED:
                    self._had.popitem(last=False)
            return True

    def _admit_urgent(
        self,
        endpoint: Endpoint[Any, Any],
        key: str,
        query: zenoh.Query,
        due: Due | None,
        jobs: queue.Queue[CallJob | None],
        arrived: float,
    ) -> bool | None:
        """Join ``query`` to its key's job not yet begun, or queue a new one.

        ``None``: the host is stopping, nothing is queued.
        """
        with self._lock:
            if self._stopping:
                return None
            job = self._waiting.get(key)
            if job is not None and job.add(query, due, same=False):
                return True
            job = CallJob(endpoint, key, query, due, arrived)
            jobs.put_nowait(job)  # unbounded: never full
            self._waiting[key] = job
            return True

    def _work(self, jobs: queue.Queue[CallJob | None]) -> None:
        while (job := jobs.get()) is not None:
            try:
                self._serve(job)
            except Exception:  # a worker never dies: log, answer the next one
                log.exception("%s: failed to serve a query", job.key)
            finally:
                self._last_answer = time.monotonic()  # see REPLY_FLUSH

    def _serve(self, job: CallJob) -> None:
        """Work on ``job`` once; send its answer to every query of it."""
        result = None
        try:
            with self._lock:
                if self._waiting.get(job.key) is job:
                    del self._waiting[job.key]  # begun: a later query waits
                due = job.due()
            result = self._result(job, due)
        finally:
            with contextlib.ExitStack() as ending:  # each query finished, whatever
                for query in self._close(job):
                    ending.enter_context(query)
                    if result is not None:
                        _reply(query, job.key, result)

    def _result(self, job: CallJob, due: Due | None) -> Answer | None:
        """``job``'s answer; ``None``: dropped, its callers have stopped waiting."""
        if due is not None and due.passed and not job.endpoint.urgent:
            late = time.monotonic() - due.at
            log.info(
                "%s: dropped a request its caller left %.2f s ago (it was "
                "%.2f s on its way, by the two wall clocks)",
                job.key,
                late,
                due.transit,
            )
            return None  # finished unanswered: no one waits for it
        first = job.first
        payload: Any = first.payload if first.payload is not None else b""
        limit = self._bus.config.max_payload
        if job.endpoint.urgent and len(payload) > limit:
            payload = b""  # acted on as it arrived: answered, never refused
        with serving_until(due), arrived_at(job.arrived):
            return answer(job.endpoint, payload, job.key, limit)

    def _close(self, job: CallJob) -> list[zenoh.Query]:
        """``job``'s queries; a query of its call from now on is a new call."""
        with self._lock:
            if job.call is not None and self._calls.get((job.key, job.call)) is job:
                del self._calls[(job.key, job.call)]
            return job.close()

    def stop(self) -> None:
        """Withdraw the token; finish queued requests; then the queryables.

        The queryables go last: withdrawn while a worker was still replying,
        the reply could be lost, its caller told "no queryable answered"
        for a request that had been served (a bridge's report of a
        trajectory it watched to its end as it stopped).
        """
        with self._lock:  # a query from now on is answered at once
            self._stopping = True
        if self._token is not None:
            self._token.undeclare()  # type: ignore[no-untyped-call]
            self._token = None
        try:
            for _, jobs in self._workers:
                jobs.put(None, timeout=STOP_GRACE)
        except queue.Full:  # workers stuck in handlers: they are daemons
            log.warning("service %s: workers still busy at stop", self.name)
        for worker, _ in self._workers:
            worker.join(STOP_GRACE)
        self._workers.clear()
        time.sleep(max(0.0, self._last_answer + REPLY_FLUSH - time.monotonic()))
        for queryable in self._queryables:
            queryable.undeclare()  # type: ignore[no-untyped-call]
        self._queryables.clear()
        log.info("service %s stopped", self.name)


#: ``_admit``'s answer to a query asked only if its call is new, whose call
#: the host has had.
_HAD = object()


def _lane(endpoint: Endpoint[Any, Any], key: str) -> str:
    """The queue ``endpoint`` (at ``key``) is served from: ``""``, the shared one.

    An urgent endpoint always has its own.
    """
    return key if endpoint.own_worker or endpoint.urgent else ""


def _reply(query: zenoh.Query, key: str, result: Answer) -> None:
    """Send ``result`` as ``query``'s reply (an ``ok`` or an ``err``)."""
    try:
        if result.ok:
            timing = result.timing
            query.reply(
                key,
                result.body,
                encoding=zenoh.Encoding.APPLICATION_JSON,
                attachment=None if timing is None else timing.to_json(),
            )
        else:
            query.reply_err(result.body, encoding=zenoh.Encoding.APPLICATION_JSON)
    except zenoh.ZError as error:  # the caller gave up or went away
        log.warning("%s: could not reply (%s)", key, error)
