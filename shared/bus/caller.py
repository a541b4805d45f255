"""Ask a service over Zenoh and get its typed reply, or its typed error.

The caller never hangs: it checks the service's liveliness token first (so a
stopped service is reported at once), every ``get`` carries a timeout, and a
wait ends as soon as the process has lost its router (``_watching``).

A repeatable route (``Route.repeatable``: the answer depends on the request
alone) is asked once more if no answer has come after ``resend_after``
seconds, and the first answer to either query wins. On loopback with
eclipse-zenoh 1.10.2 a query now and then never reaches its queryable (the
service logs no such request, and the caller would wait its whole timeout);
we saw it between once in a few hundred and once in twenty thousand
queries. The second query covers that, and costs a duplicate computation
only where a service really is that slow.

The second query is also sent at once (after ``EMPTY_PAUSE``) when the first
ends without any reply while the service's token is alive: Zenoh then had no
route to its queryable and the query reached no one (eclipse-zenoh issue
2767: just after a queryable or a session starts, the route can be empty for
a moment; we saw it twice in one CI run, right after a service restart and a
client's first call). Our services answer every query they receive, so an
empty end is not an answer lost.

A call that is not repeatable (a robot motion above all) is asked again
only on the proof that its query reached no one: it ended without any reply
within ``NO_ROUTE_END`` of being sent (a query Zenoh routes nowhere ends at
once: under a millisecond measured; one a queryable got ends with a reply,
or when its service's session ends), and the service's token is still
there, asked of the router afresh (a service that died with the query ends
it so, and takes its token with it). Any other empty end reports the
service unavailable. That is a guess, not a proof: a query a service got
also ends so if its reply is lost (a router's access control that refuses
the reply but not the query: the service's work was done twice). So the
second query says it is asked only if the service never had the call
(``CallerBudget.again``), and a service that had it refuses it.

Both queries carry one call id (``CallerBudget.call``): a service that
still has the first queued or running answers the second from the same
work (``shared.bus.call_job``), never ``service_busy``. A ``service_busy``
answer to the second query while the first is still open (a service that
does not know call ids) is not taken as the answer either: the first may
still be worked on, and busy must mean nothing was done. It is the answer
only once the first query has ended without one.
"""

from __future__ import annotations

import itertools
import queue
import threading
import time
import uuid
from collections.abc import Callable
from typing import Any

import zenoh

from shared.bus.config import MAX_WAIT
from shared.bus.deadline import budget_attachment
from shared.bus.elsewhere import HINT_TIMEOUT, alive_elsewhere, elsewhere_hint
from shared.bus.keys import alive_key
from shared.bus.liveness import QUERY_TIMEOUT, AliveServices
from shared.bus.robot_routes import BRIDGE
from shared.bus.route import Rep, Route
from shared.bus.session import has_router, has_router_or_peer
from shared.errors import (
    InvalidInputError,
    RemoteError,
    RequestTimeoutError,
    ServiceBusyError,
    ServiceUnavailableError,
)
from shared.messages import ErrorReply, Message, ServiceTiming, parse

#: Payload of Zenoh's own error reply when a query times out.
ZENOH_TIMEOUT = b"Timeout"
#: Pause before asking again after a query ended without any reply [s].
EMPTY_PAUSE = 0.05
#: Longest time after which a query that ends without any reply likely
#: reached no queryable [s]: Zenoh ends one it routes nowhere in under 1 ms,
#: but the caller's reply reader saw that end over 0.05 s later on a loaded
#: machine (a CI run), and a 0.5 s window still missed it now and then in
#: CI. A service that had the call refuses the second query
#: (``CallerBudget.again``), so the margin is no risk of working twice.
NO_ROUTE_END = 0.9
#: Longest wait for the router's answer whether a service's token is still
#: there, after a query ended without a reply [s]: its answer comes at once
#: either way unless the machine is loaded (0.5 s was missed in CI, the
#: call then told unavailable).
STILL_THERE_WAIT = 2.0
#: Longest time between two calls of a call's ``check`` while it waits [s].
CHECK_EVERY = 0.5
#: A call's check while it waits: raises to stop waiting.
Check = Callable[[], None]
#: Name of the threads that read a query's replies (``_forward``).
FORWARDER = "zenoh-reply-forwarder"
#: A query's number in its call (0: the first) and a reply to it, or
#: ``None`` once it has ended.
_Item = tuple[int, zenoh.Reply | None]

#: Forwarders still reading a query (the caller may have its answer
#: already), by the ``id`` of their query's session.
_forwarders: dict[int, set[threading.Thread]] = {}
_forwarders_lock = threading.Lock()


def answered(
    session: zenoh.Session,
    alive: AliveServices,
    namespace: str,
    route: Route[Any, Any],
    request: Message | str | bytes,
    timeout: float,
    resend_after: float | None = None,
    repeat: bool | None = None,
    unseen: bool = False,
    check: Check | None = None,
) -> zenoh.Reply:
    """Send ``request`` to ``route``; Zenoh's reply (an ``ok`` or an ``err``).

    ``read_reply`` turns it into the typed reply, or raises the service's
    own typed error.

    Args:
        session: An open session.
        alive: The live services seen from ``session``.
        namespace: The namespace, e.g. ``"armplan"``.
        route: The route asked.
        request: The request message, or raw JSON (sent as is).
        timeout: Longest wait for the reply [s].
        resend_after: Ask again once if no answer has come after this long
            [s] (if ``repeat``); ``None``: ask once.
        repeat: Whether asking twice is harmless; default ``route.repeatable``.
        unseen: Send it even if the service's liveliness token is not seen
            (an operator's stop: a bridge whose token is lost may still
            serve); its absence is said only if no reply comes.
        check: Called about every :data:`CHECK_EVERY` seconds while the
            answer is waited for; what it raises ends the wait (the queries
            are left to end on their own): the planner stops waiting for a
            stage once every caller of its plan has gone.

    Raises:
        ServiceUnavailableError: if the route's service is not running.
        RequestTimeoutError: if it does not answer within ``timeout``.
    """
    key = route.key(namespace)
    start = time.monotonic()
    if not unseen and not alive.is_alive(route.service, min(QUERY_TIMEOUT, timeout)):
        if timeout < QUERY_TIMEOUT and time.monotonic() - start >= 0.9 * timeout:
            # the router's answer did not come within the call's own time: a
            # timed-out liveliness query reads as no token, yet nothing was
            # learnt (--timeout 0.001 on a loaded machine was told "absent")
            raise RequestTimeoutError(route.service, key=key, timeout=timeout)
        raise _absent(session, namespace, route, start + timeout)
    repeatable = route.repeatable if repeat is None else repeat
    resend = resend_after if repeatable else None

    def still_there() -> bool:
        """Whether the service's token is there, asked of the router afresh.

        Asked twice if the first answer lacks it: in two CI runs in a row
        a call whose query reached no one was told unavailable; the suspect
        (not confirmed) is a liveliness query made just as a query ends
        coming back empty.
        """
        for _ in range(2):
            alive.forget(route.service)
            if alive.is_alive(route.service, STILL_THERE_WAIT):
                return True
            time.sleep(EMPTY_PAUSE)
        return False

    watch = _watching(session, route.service, key, check)
    reply = _ask(
        session, key, encode(request), start + timeout, resend, still_there, watch
    )
    if reply is not None:
        return reply
    if unseen and not alive.is_alive(route.service, QUERY_TIMEOUT):
        raise _absent(
            session,
            namespace,
            route,
            start + timeout,
            "; the query was sent all the same: nothing answered",
        )
    if time.monotonic() - start >= 0.9 * timeout:
        raise RequestTimeoutError(route.service, key=key, timeout=timeout)
    alive.forget(route.service)
    reason = (
        "no queryable answered (it just stopped, or a secured router's access "
        "control refused this user the query)"
    )
    raise ServiceUnavailableError(
        route.service, key=key, reason=_router_lost(session) or reason
    )


def _ask(
    session: zenoh.Session,
    key: str,
    body: bytes,
    deadline: float,
    resend_after: float | None,
    still_there: Callable[[], bool] = lambda: False,
    check: Check | None = None,
) -> zenoh.Reply | None:
    """The first answer to ``body`` at ``key`` before ``deadline`` (monotonic [s]).

    Asks again once after ``resend_after`` [s] without an answer, or at once
    if the first query ends without any reply (``None``: never). With
    ``resend_after`` ``None``, asks again once only if the first query ended
    without any reply within :data:`NO_ROUTE_END` and ``still_there()``
    (the service's token is there): it likely reached no one, and the
    second query says so (``CallerBudget.again``). Returns
    ``None`` if every query ended without a reply; Zenoh's own timeout reply
    is returned only if no query got anything else, and a ``service_busy``
    to one query only once no other query is open (see the module's
    docstring). Every wait is clamped to ``MAX_WAIT`` and the resend to the
    deadline: a wait of 1e10 s overflowed ``queue.get``, one of 1e300 s was
    a "negative timeout" to Zenoh.
    """
    deadline = min(deadline, time.monotonic() + MAX_WAIT)
    inbox: queue.SimpleQueue[_Item] = queue.SimpleQueue()
    call = uuid.uuid4().hex  # the same on both queries: see CallerBudget.call
    caller = str(session.zid())  # whose caller token says it is still there
    open_queries: set[int] = set()
    numbers = itertools.count()

    def send(again: bool = False) -> None:
        left = max(deadline - time.monotonic(), 1e-3)
        told = budget_attachment(left, call=call, session=caller, again=again)
        replies = session.get(
            key,
            payload=body,
            encoding=zenoh.Encoding.APPLICATION_JSON,
            timeout=left,
            attachment=told,
        )
        number = next(numbers)
        open_queries.add(number)
        _start_forwarder(id(session), number, replies, inbox)

    first_sent = time.monotonic()
    send()
    timed_out = busy = None
    resend_at = (
        None if resend_after is None else min(time.monotonic() + resend_after, deadline)
    )

    def reached_no_one(number: int) -> bool:
        """Whether query ``number``, ended without a reply, surely reached no one."""
        quick = number == 0 and time.monotonic() - first_sent < NO_ROUTE_END
        return resend_after is None and quick and still_there()

    while open_queries:
        wait_until = deadline + 1.0 if resend_at is None else resend_at
        left = max(wait_until - time.monotonic(), 0.0)
        try:
            number, item = inbox.get(
                timeout=left if check is None else min(left, CHECK_EVERY)
            )
        except queue.Empty:
            if check is not None and time.monotonic() < wait_until:
                check()  # raises to stop waiting
                continue
            if resend_at is None:  # Zenoh never closed its query: give up
                break
            resend_at = None
            if time.monotonic() < deadline:
                send()
            continue
        if item is None:
            open_queries.discard(number)
            if (
                not open_queries
                and not timed_out
                and (resend_at is not None or reached_no_one(number))
            ):
                # Ended without a reply: Zenoh found no route to a queryable
                # (see the module's docstring) and the query reached no one.
                # Ask again, once; a call that is not repeatable only if the
                # service never had it (CallerBudget.again).
                once = resend_after is None
                resend_at = None
                time.sleep(EMPTY_PAUSE)
                if time.monotonic() < deadline:
                    send(again=once)
        elif _is_timeout(item):
            timed_out = item
        elif _is_busy(item) and open_queries - {number}:
            busy = item  # the other query may still be worked on: wait for it
        else:
            return item
    return timed_out or busy


def _watching(
    session: zenoh.Session, service: str, key: str, check: Check | None
) -> Check:
    """``check``, then a stop once ``session`` has no connection left.

    A query whose connection closes can never be answered: its reply would
    come back the way it went. Zenoh ended every such query at once in the
    runs we made by hand, yet in one CI run a plan sent as the router was
    killed waited its whole 30 s timeout (why is not known) while the calls
    beside it were told at once that the router was lost. Without a router
    or a peer, the wait now ends within :data:`CHECK_EVERY`, with the same
    error (``docs/faults.md``).
    """

    def watch() -> None:
        if check is not None:
            check()
        if not has_router_or_peer(session):
            raise ServiceUnavailableError(
                service,
                key=key,
                reason="this process lost its connection to the Zenoh router "
                "while it waited for the answer",
            )

    return watch


def _start_forwarder(
    session: int,
    number: int,
    replies: zenoh.Handler[zenoh.Reply],
    inbox: queue.SimpleQueue[_Item],
) -> None:
    """Read ``replies`` into ``inbox`` on a thread of its own (``_forward``).

    ``session``: the ``id`` of the query's session; ``number``: the query's
    number in its call.
    """
    thread = threading.Thread(
        target=_forward,
        args=(session, number, replies, inbox),
        name=FORWARDER,
        daemon=True,
    )
    with _forwarders_lock:
        _forwarders.setdefault(session, set()).add(thread)
    thread.start()


def join_forwarders(session: zenoh.Session, timeout: float) -> None:
    """Wait up to ``timeout`` [s] in all for ``session``'s reply forwarders to end.

    Called once the session is closed, which ends its queries. A forwarder
    that the first answer left reading a query still open (its queryable
    has not finished it) must not outlive the interpreter: a daemon thread
    still inside Zenoh's ``recv`` when Python finalises is ended by a forced
    unwind that Zenoh's Rust code catches, and the process aborts ("FATAL:
    exception not rethrown", exit 134) after its work is done; a client of
    the bridge did, about once in fifteen runs.
    """
    end = time.monotonic() + timeout
    with _forwarders_lock:
        pending = list(_forwarders.get(id(session), ()))
    for thread in pending:
        thread.join(max(end - time.monotonic(), 0.0))


def _forward(
    session: int,
    number: int,
    replies: zenoh.Handler[zenoh.Reply],
    inbox: queue.SimpleQueue[_Item],
) -> None:
    """Put query ``number``'s replies into ``inbox``, then ``None`` when it ends.

    Read from Zenoh's channel in order: a callback's end-of-query call can
    overtake its last reply (both run on different threads), which made a
    reply look missing.
    """
    try:
        for reply in replies:
            inbox.put((number, reply))
        inbox.put((number, None))
    finally:
        with _forwarders_lock:
            threads = _forwarders.get(session, set())
            threads.discard(threading.current_thread())
            if not threads:
                _forwarders.pop(session, None)


def _is_timeout(reply: zenoh.Reply) -> bool:
    """Whether ``reply`` is Zenoh's own error reply for a query that timed out."""
    return reply.err is not None and reply.err.payload.to_bytes() == ZENOH_TIMEOUT


def _is_busy(reply: zenoh.Reply) -> bool:
    """Whether ``reply`` is a service's ``service_busy`` error reply."""
    if reply.err is None:
        return False
    try:
        error = parse(ErrorReply, reply.err.payload.to_bytes())
    except InvalidInputError:
        return False
    return error.kind == ServiceBusyError.kind


def _absent(
    session: zenoh.Session,
    namespace: str,
    route: Route[Any, Any],
    due: float,
    then: str = "",
) -> ServiceUnavailableError:
    """The error for ``route``'s service without a token: why, and ``then``.

    Why: no router connection, or no token at its key; then (with a router)
    the other namespaces where the service is alive, if any, asked for only
    until ``due`` (``time.monotonic()`` [s]), the call's own deadline: the
    hint never makes a call late (a stage of the planner's, under its
    caller's deadline), it is left out instead.
    """
    key = route.key(namespace)
    lost = _router_lost(session)
    if lost:
        return ServiceUnavailableError(route.service, key=key, reason=lost + then)
    left = min(HINT_TIMEOUT, due - time.monotonic())
    found = alive_elsewhere(session, namespace, [route.service], left)
    return ServiceUnavailableError(
        route.service,
        key=key,
        reason=f"no liveliness token at {alive_key(namespace, route.service)} "
        f"(is it started, e.g. by {_starter(route.service)}?){then}"
        f"{elsewhere_hint(found)}",
        elsewhere=found,
    )


def _starter(service: str) -> str:
    """The command that starts ``service``, for a hint.

    Plain ``armplan up`` starts no bridge: ``armplan stop`` right after it
    asked "is it started, e.g. by `armplan up`?" of an operator who had
    just run that; a secured bridge runs as ``python -m bridge.serve``, and
    a secured service as ``python -m services.<name>`` (``armplan up``
    refuses a secured set).
    """
    if service == BRIDGE:
        return (
            "`armplan up --with-sim`, `armplan up --robot URL` or "
            "`python -m bridge.serve`"
        )
    return f"`armplan up` or `python -m services.{service}`"


def _router_lost(session: zenoh.Session) -> str:
    """A reason if the session has no router connection now, else ``""``."""
    if has_router(session):
        return ""
    return "this process has lost its connection to the Zenoh router"


def encode(request: Message | str | bytes) -> bytes:
    """The request's JSON [bytes]."""
    if isinstance(request, Message):
        return request.to_json().encode()
    return request.encode() if isinstance(request, str) else bytes(request)


def read_reply(
    route: Route[Any, Rep], reply: zenoh.Reply, key: str, timeout: float
) -> Rep:
    """The typed reply, or raise the typed error the service sent.

    Args:
        route: The route asked.
        reply: Zenoh's reply.
        key: The full key (for messages).
        timeout: The wait that was allowed [s] (for messages).
    """
    if reply.ok is not None:
        return _parse_reply(route, reply.ok.payload.to_bytes(), key)
    assert reply.err is not None
    body = reply.err.payload.to_bytes()
    if body == ZENOH_TIMEOUT:
        raise RequestTimeoutError(route.service, key=key, timeout=timeout)
    try:
        error = parse(ErrorReply, body)
    except InvalidInputError:
        shown = body[:200].decode(errors="replace")
        raise RemoteError(
            f"service {route.service!r} answered {key} with an error that is not "
            f"an armplan ErrorReply: {shown!r}",
            service=route.service,
            key=key,
        ) from None
    raise error.to_error()


def service_timing(reply: zenoh.Reply) -> ServiceTiming | None:
    """The service's account of its time (its reply's attachment), if any.

    ``None`` for an error reply, or a reply without a readable one (a
    service that is not armplan's).
    """
    if reply.ok is None or reply.ok.attachment is None:
        return None
    try:
        return parse(ServiceTiming, reply.ok.attachment.to_bytes())
    except InvalidInputError:
        return None


def _parse_reply(route: Route[Any, Rep], body: bytes, key: str) -> Rep:
    """The reply message; a malformed one is the service's fault, not the caller's."""
    try:
        return parse(route.reply, body)
    except InvalidInputError as error:
        raise RemoteError(
            f"service {route.service!r} answered {key} with a malformed reply: "
            f"{error.message}",
            service=route.service,
            key=key,
        ) from None
