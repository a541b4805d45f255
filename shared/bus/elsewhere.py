"""Where else a missing service is alive: the hint of a "not alive" error.

``armplan replay --namespace lab2 --wait-for bridge`` with the bridge running
under ``armplan`` on the same router said only "not alive after 5 s". Once a
wait has failed (never while all is well), one liveliness query per missing
service on ``**/alive/<service>`` finds the other namespaces where it holds
a token, and the error names them with the option that reaches them.

Best effort: the queries share a short timeout, and a router that refuses
them (a secured router's access control) or fails just leaves the hint out.
"""

from __future__ import annotations

import time
from collections.abc import Iterable

import zenoh

from shared.bus.keys import (
    alive_anywhere,
    alive_key,
    check_path,
    namespace_from_alive_key,
)
from shared.errors import InvalidInputError, ServiceUnavailableError
from shared.text.counted import agreeing

#: Longest wait for the router's answers to the hint's queries, all together [s].
HINT_TIMEOUT = 0.5
#: Most namespaces a hint names for one service.
HINT_NAMES = 3


def alive_elsewhere(
    session: zenoh.Session,
    namespace: str,
    services: Iterable[str],
    timeout: float = HINT_TIMEOUT,
) -> dict[str, list[str]]:
    """The namespaces other than ``namespace`` where each of ``services`` is alive.

    Args:
        session: An open session.
        namespace: The namespace looked in, e.g. ``"lab2"`` (left out).
        services: Service names, e.g. ``["bridge"]``.
        timeout: Longest wait for all the answers together [s].

    Returns:
        Sorted namespaces by service, only services found somewhere; ``{}``
        if the router refused or failed the query.
    """
    found: dict[str, list[str]] = {}
    deadline = time.monotonic() + timeout
    for service in sorted(set(services)):
        left = deadline - time.monotonic()
        if left <= 0:
            break
        spaces = _namespaces_of(session, service, left)
        spaces.discard(namespace)
        if spaces:
            found[service] = sorted(spaces)
    return found


def _namespaces_of(session: zenoh.Session, service: str, timeout: float) -> set[str]:
    """Every valid namespace where ``service`` holds a token (none if refused)."""
    try:
        replies = list(
            session.liveliness().get(alive_anywhere(service), timeout=timeout)
        )
    except zenoh.ZError:  # a hint only: no hint
        return set()
    keys = (str(reply.ok.key_expr) for reply in replies if reply.ok is not None)
    return {
        ns for ns in (namespace_from_alive_key(k, service) for k in keys) if _valid(ns)
    }


def _valid(namespace: str) -> bool:
    """Whether ``namespace`` is one ``--namespace`` takes (a name from the network)."""
    try:
        check_path(namespace, "namespace")
    except InvalidInputError:
        return False
    return True


def elsewhere_hint(found: dict[str, list[str]]) -> str:
    """``"; 'bridge' is alive in namespace 'lab1' (--namespace lab1)"``, or ``""``.

    At most ``HINT_NAMES`` namespaces are named per service, then how many
    more: the names come from the network, a router may hold thousands.
    """
    return "".join(
        f"; {service!r} is alive in {_names(spaces)} (--namespace {spaces[0]})"
        for service, spaces in found.items()
    )


def _names(spaces: list[str]) -> str:
    """``namespace 'lab1'``, ``namespaces 'a', 'b'``, ``... and 7 more``."""
    shown = ", ".join(repr(ns) for ns in spaces[:HINT_NAMES])
    more = len(spaces) - HINT_NAMES
    rest = f" and {more} more" if more > 0 else ""
    return f"{agreeing(len(spaces), 'namespace')} {shown}{rest}"


def not_alive_error(
    session: zenoh.Session,
    namespace: str,
    missing: list[str],
    waited: float,
    note: str = "",
) -> ServiceUnavailableError:
    """The error for ``missing`` services still without a token after a wait.

    It names each token key watched, and where else on the router a missing
    service is alive (:func:`alive_elsewhere`).

    Args:
        session: An open session on the router watched.
        namespace: The namespace watched, e.g. ``"armplan"``.
        missing: The services without a token, e.g. ``["bridge"]``.
        waited: How long the wait was [s].
        note: More to say after the keys (e.g. a misspelt service's hint).
    """
    keys = ", ".join(alive_key(namespace, name) for name in missing)
    found = alive_elsewhere(session, namespace, missing)
    return ServiceUnavailableError(
        ", ".join(missing),
        reason=f"no liveliness token on {keys} after {waited:g} s"
        f"{note}{elsewhere_hint(found)}",
        elsewhere=found,
    )
