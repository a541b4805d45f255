"""What became of one request: its result, a typed error, or nothing.

:func:`send` asks a route once and never raises; it sorts the answer into
an :class:`Outcome`:

- ``succeeded``: the reply message came back;
- ``typed``: an armplan error that says what went wrong (invalid input,
  service unavailable, ...), including a stage's timeout relayed by the
  planner (the planner answered);
- ``unclear``: an answer, but no clear error: ``internal_error`` (the
  service hit a bug) or ``remote_error`` (not an armplan error reply);
- ``lost``: no answer within the timeout (this client's own
  ``request_timeout``), an answer only after it, or a failure that is not
  an armplan error at all.
"""

from __future__ import annotations

import enum
import time
from typing import Any, NamedTuple

from shared.bus import Bus, Route
from shared.errors import (
    ArmplanError,
    InternalServiceError,
    RemoteError,
    RequestTimeoutError,
)
from shared.messages import Message

#: Time a call may overrun its timeout before its answer counts as lost [s]
#: (the liveliness check and a loaded machine's scheduling).
SLACK = 2.0


class Outcome(enum.Enum):
    """How a request ended."""

    SUCCEEDED = "succeeded"
    TYPED = "typed"
    UNCLEAR = "unclear"
    LOST = "lost"


class Result(NamedTuple):
    """One request's end.

    Attributes:
        route: The route's path, e.g. ``"plan"``.
        outcome: How it ended.
        kind: The error's kind (``"service_unavailable"``), ``""`` on success.
        service: The service the error names, if any.
        message: The error's message, ``""`` on success.
        seconds: Time from sending to the answer [s].
    """

    route: str
    outcome: Outcome
    kind: str = ""
    service: str = ""
    message: str = ""
    seconds: float = 0.0


class Call(NamedTuple):
    """A request to send.

    Attributes:
        route: Where to send it.
        payload: The request message, or raw bytes sent as they are.
    """

    route: Route[Any, Any]
    payload: Message | bytes


def send(bus: Bus, call: Call, timeout: float) -> Result:
    """Send ``call`` once, wait up to ``timeout`` [s]; how it ended (never raises)."""
    start = time.monotonic()
    key = call.route.key(bus.config.namespace)
    try:
        bus.call(call.route, call.payload, timeout=timeout)
        result = Result(call.route.path, Outcome.SUCCEEDED)
    except ArmplanError as error:
        result = _failed(call.route.path, error, key)
    except Exception as error:  # not an armplan error: nobody answered clearly
        text = f"{type(error).__name__}: {error}"
        result = Result(call.route.path, Outcome.LOST, "untyped", "", text)
    seconds = time.monotonic() - start
    if seconds > timeout + SLACK and result.outcome is not Outcome.LOST:
        late = f"answered after {seconds:.1f} s, timeout {timeout:.1f} s"
        result = result._replace(outcome=Outcome.LOST, kind="late", message=late)
    return result._replace(seconds=seconds)


def _failed(path: str, error: ArmplanError, key: str) -> Result:
    service = str(error.evidence.get("service", ""))
    outcome = Outcome.TYPED
    if isinstance(error, RequestTimeoutError) and error.evidence.get("key") == key:
        outcome = Outcome.LOST  # this client waited in vain (not a relayed one)
    elif isinstance(error, InternalServiceError | RemoteError):
        outcome = Outcome.UNCLEAR
    return Result(path, outcome, error.kind, service, error.message)
