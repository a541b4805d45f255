"""Ask a service over Zenoh and get its typed reply, or its typed error.

The caller never hangs: it checks the service's liveliness token first (so a
stopped service is reported at once), and every ``get`` carries a timeout.
"""

from __future__ import annotations

import time
from typing import Any

import zenoh

from shared.bus.keys import alive_key
from shared.bus.liveness import QUERY_TIMEOUT, AliveServices
from shared.bus.route import Rep, Route
from shared.errors import (
    InvalidInputError,
    RemoteError,
    RequestTimeoutError,
    ServiceUnavailableError,
)
from shared.messages import ErrorReply, Message, parse

#: Payload of Zenoh's own error reply when a query times out.
ZENOH_TIMEOUT = b"Timeout"


def call(
    session: zenoh.Session,
    alive: AliveServices,
    namespace: str,
    route: Route[Any, Rep],
    request: Message | str | bytes,
    timeout: float,
) -> Rep:
    """Send ``request`` to ``route`` and return its reply.

    Args:
        session: An open session.
        alive: The live services seen from ``session``.
        namespace: The namespace, e.g. ``"armplan"``.
        route: The route asked.
        request: The request message, or raw JSON (sent as is).
        timeout: Longest wait for the reply [s].

    Raises:
        ServiceUnavailableError: if the route's service is not running.
        RequestTimeoutError: if it does not answer within ``timeout``.
        ArmplanError: the service's own typed error, rebuilt.
    """
    key = route.key(namespace)
    start = time.monotonic()
    if not alive.is_alive(route.service, min(QUERY_TIMEOUT, timeout)):
        raise ServiceUnavailableError(
            route.service, key=key, reason=_why_absent(session, namespace, route)
        )
    left = max(timeout - (time.monotonic() - start), 1e-3)
    replies = session.get(
        key,
        payload=encode(request),
        encoding=zenoh.Encoding.APPLICATION_JSON,
        timeout=left,
    )
    for reply in replies:
        return read_reply(route, reply, key, timeout)
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


def _why_absent(session: zenoh.Session, namespace: str, route: Route[Any, Any]) -> str:
    """Why a service looks absent: no router connection, or no token."""
    return _router_lost(session) or (
        f"no liveliness token at {alive_key(namespace, route.service)} "
        "(is it started, e.g. by `armplan up`?)"
    )


def _router_lost(session: zenoh.Session) -> str:
    """A reason if the session has no router connection now, else ``""``."""
    if session.info.routers_zid():
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
