"""The wire format of a service: request bytes in, reply or error bytes out.

Pure functions, no Zenoh: :func:`answer` is everything a service does with a
request (size check, validation with ``parse``, the handler, the reply JSON),
and :func:`reply_error` is how any failure becomes an ``ErrorReply``.
"""

from __future__ import annotations

import logging
import time
from typing import Any, NamedTuple, Protocol

from shared.bus.route import Endpoint
from shared.errors import ArmplanError, InternalServiceError, PayloadTooLargeError
from shared.messages import ErrorReply, ServiceTiming, parse

log = logging.getLogger("armplan.bus")


class Payload(Protocol):
    """Request bytes: ``bytes``, or Zenoh's ``ZBytes`` (sized before copying)."""

    def __len__(self) -> int: ...

    def __bytes__(self) -> bytes: ...


class Answer(NamedTuple):
    """What a service sends back.

    Attributes:
        ok: ``True`` for a reply, ``False`` for a ``reply_err``.
        body: The reply's or the ``ErrorReply``'s JSON [UTF-8 bytes].
        timing: Where the request's time went (a reply only).
    """

    ok: bool
    body: bytes
    timing: ServiceTiming | None = None


def answer(
    endpoint: Endpoint[Any, Any], payload: Payload, key: str, limit: int
) -> Answer:
    """The answer to one request; never raises.

    Args:
        endpoint: The route and its handler.
        payload: The request's JSON [bytes]; empty means ``{}``.
        key: The full key expression (for error messages).
        limit: Largest payload accepted [bytes].
    """
    try:
        if len(payload) > limit:
            raise PayloadTooLargeError(size=len(payload), limit=limit, key=key)
        start = time.perf_counter()
        data = bytes(payload)
        request = (
            parse(endpoint.route.request, data or b"{}")
            if endpoint.parse is None
            else endpoint.parse(data)
        )
        parsed = time.perf_counter()
        result = endpoint.handle(request)
        handled = time.perf_counter()
        if not isinstance(result, endpoint.route.reply):
            raise TypeError(
                f"handler returned {type(result).__name__}, "
                f"not {endpoint.route.reply.__name__}"
            )
        body = result.to_json().encode()
        timing = ServiceTiming(
            parse=parsed - start,
            handle=handled - parsed,
            reply_json=time.perf_counter() - handled,
        )
        return Answer(True, body, timing)
    except ArmplanError as error:
        log.info("%s: %s", key, error.message)
        return Answer(False, reply_error(error))
    except Exception as error:
        log.exception("%s: unexpected %s", key, type(error).__name__)
        internal = InternalServiceError(
            endpoint.route.service,
            key=key,
            error_type=type(error).__name__,
            detail=str(error)[:500],
        )
        return Answer(False, reply_error(internal))


def reply_error(error: ArmplanError) -> bytes:
    """The ``ErrorReply`` JSON of ``error`` [bytes], even if its evidence is odd."""
    try:
        return ErrorReply.from_error(error).to_json().encode()
    except Exception:  # evidence that does not serialise: keep kind and message
        bare = ErrorReply(kind=error.kind, message=error.message)
        return bare.to_json().encode()
