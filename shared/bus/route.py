"""A route: one key a service answers, with its request and reply messages.

A route is the contract between a service and its callers; both sides hold
the same object, so the key and the message types cannot drift apart.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from shared.bus.keys import check_name, check_path, service_key
from shared.messages import Message

Req = TypeVar("Req", bound=Message)
Rep = TypeVar("Rep", bound=Message)


class NoArguments(Message):
    """The request of a query that takes no arguments (an empty payload is ``{}``)."""


@dataclass(frozen=True)
class Route(Generic[Req, Rep]):
    """One key a service answers.

    Attributes:
        service: Name of the service process that answers it, e.g. ``"ik"``;
            callers check its liveliness token before asking.
        path: The key under the namespace, e.g. ``"ik/solve"``.
        request: The request message type.
        reply: The reply message type.
        repeatable: The answer depends on the request alone and answering
            changes nothing (no publication, no new state): a caller may ask
            twice and take the first answer (see ``caller.answered``).
    """

    service: str
    path: str
    request: type[Req]
    reply: type[Rep]
    repeatable: bool = False

    def __post_init__(self) -> None:
        check_name(self.service)
        check_path(self.path, "route path")

    def key(self, namespace: str) -> str:
        """The full key expression, e.g. ``armplan/ik/solve``."""
        return service_key(namespace, self.path)


@dataclass(frozen=True)
class Endpoint(Generic[Req, Rep]):
    """A route and the in-process function that answers it.

    Attributes:
        route: The route served.
        handle: Request in, reply out; raises an ``ArmplanError`` to refuse.
        own_worker: Answered by a worker of its own, never queued behind
            the service's other requests: a stop must be served while the
            workers are blocked playing movements (``bridge/stop``).
        at_once: Run on Zenoh's own thread as each query arrives, with its
            raw payload (``b""`` if none or over the size limit), before
            anything is parsed, queued or checked against its caller's
            deadline: what must happen whatever becomes of the reply (a
            stop ordering the arm stopped). It must not block nor raise
            (an exception is logged). An endpoint with one is *urgent*:
            its queries are never refused busy nor dropped for their
            caller's deadline, and a query that comes while one is queued
            (not yet worked on) joins it and gets its answer.
        parse: Reads the request from the raw payload instead of the
            route's message, e.g. leniently; it raises an ``ArmplanError``
            to refuse. None: the route's request message, strictly.
    """

    route: Route[Req, Rep]
    handle: Callable[[Req], Rep]
    own_worker: bool = False
    at_once: Callable[[bytes], None] | None = None
    parse: Callable[[bytes], Req] | None = None

    @property
    def urgent(self) -> bool:
        """Never refused busy nor dropped (see ``at_once``)."""
        return self.at_once is not None
