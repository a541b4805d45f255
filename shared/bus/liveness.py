"""Which services are running: their liveliness tokens, watched and queried.

Every service declares ``<ns>/alive/<service>`` while it runs; Zenoh removes
the token when the service's session ends, however it ends. A client asks
the router once per service (a liveliness query) and then keeps its set of
live services current with a liveliness subscriber (token removed: out of the
set; token declared again after a restart: back in).

The subscriber is declared without ``history``: in eclipse-zenoh 1.10.2 a
liveliness subscriber with ``history=True`` declared just before a liveliness
query makes that query return no tokens at all.
"""

from __future__ import annotations

import threading

import zenoh

from shared.bus.keys import (
    ALIVE,
    alive_key,
    alive_pattern,
    service_from_alive_key,
)

#: Longest wait for the router's answer to a liveliness query [s]. It
#: answers at once, the token there or not (0.5 ms measured; without a
#: router the query ends at once too), unless the machine is loaded: a
#: fresh-clone CI run saw 0.5 s missed and a live service told absent ("no
#: liveliness token"). A query that times out reads as no token, so the wait
#: is long: a bridge's check that no other bridge serves relies on it too.
QUERY_TIMEOUT = 3.0


class AliveServices:
    """The live services of one namespace, seen from one session."""

    def __init__(self, session: zenoh.Session, namespace: str) -> None:
        self._session = session
        self._namespace = namespace
        self._names: set[str] = set()
        self._lock = threading.Lock()
        self._subscriber = session.liveliness().declare_subscriber(
            alive_pattern(namespace), self._on_sample
        )

    def _on_sample(self, sample: zenoh.Sample) -> None:
        name = service_from_alive_key(self._namespace, str(sample.key_expr))
        with self._lock:
            if sample.kind == zenoh.SampleKind.PUT:
                self._names.add(name)
            else:
                self._names.discard(name)

    def is_alive(self, service: str, timeout: float = QUERY_TIMEOUT) -> bool:
        """Whether ``service`` holds its token (asks the router if not known).

        Args:
            service: The service's name, e.g. ``"ik"``.
            timeout: Longest wait for the router's answer [s].
        """
        with self._lock:
            if service in self._names:
                return True
        key = alive_key(self._namespace, service)
        found = any(r.ok is not None for r in self._query(key, timeout))
        if found:
            with self._lock:
                self._names.add(service)
        return found

    def forget(self, service: str) -> None:
        """Drop ``service`` from the set (it stopped answering); asked again next."""
        with self._lock:
            self._names.discard(service)

    def _query(self, key: str, timeout: float) -> list[zenoh.Reply]:
        return list(self._session.liveliness().get(key, timeout=timeout))

    def close(self) -> None:
        """Stop watching (before the session closes)."""
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]


def list_alive(
    session: zenoh.Session, namespace: str, timeout: float = QUERY_TIMEOUT
) -> list[str]:
    """Names of every service holding a token now, sorted.

    Args:
        session: An open session.
        namespace: The namespace, e.g. ``"armplan"``.
        timeout: Longest wait for the router's answer [s].
    """
    names = {
        service_from_alive_key(namespace, str(reply.ok.key_expr))
        for reply in session.liveliness().get(alive_pattern(namespace), timeout=timeout)
        if reply.ok is not None
    }
    return sorted(names)


def alive_by_namespace(
    session: zenoh.Session, timeout: float = QUERY_TIMEOUT
) -> dict[str, list[str]]:
    """Every namespace with a service holding a token now: its services, sorted.

    One liveliness query on ``**/alive/*`` (a secured router may answer only
    for the namespaces its user may see).

    Args:
        session: An open session.
        timeout: Longest wait for the router's answer [s].
    """
    found: dict[str, set[str]] = {}
    for reply in session.liveliness().get(alive_pattern("**"), timeout=timeout):
        if reply.ok is None:
            continue
        namespace, _, service = str(reply.ok.key_expr).rpartition(f"/{ALIVE}/")
        found.setdefault(namespace, set()).add(service)
    return {namespace: sorted(found[namespace]) for namespace in sorted(found)}
