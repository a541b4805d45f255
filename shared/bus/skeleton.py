"""A stand-in handler for a route whose algorithm is not wired yet.

The service still starts, announces itself and answers every request, with a
typed ``endpoint_not_wired`` error naming what is missing, instead of leaving
callers to time out.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from shared.bus.route import Rep, Route
from shared.errors import EndpointNotWiredError
from shared.messages import Message


def not_wired(
    route: Route[Any, Rep], namespace: str, todo: str
) -> Callable[[Message], Rep]:
    """A handler for ``route`` that refuses every request, naming ``todo``.

    Args:
        route: The route served.
        namespace: The namespace (for the key in the message).
        todo: What is missing, e.g. ``"the planner (services.planner)"``.
    """
    key = route.key(namespace)

    def refuse(request: Message) -> Rep:
        raise EndpointNotWiredError(route.service, key=key, todo=todo)

    return refuse
