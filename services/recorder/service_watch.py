"""A service coming alive during a replay: the check before, the watch during.

A replay without ``--keys`` is refused when a service that would take its
messages is alive in its namespace (a bridge: ``bridge_watch``; a decide
service: ``model_check``), but a check is made once, before the first
message: a bridge started during a long replay received the rest of the
recorded trajectories and, with ``--follow``, played them on the arm.
A :class:`ServiceWatch` declares a liveliness subscriber on the service's
token (``<ns>/alive/<service>``) before the check, so a service appearing
between the check and the first message is seen too, and flags the first
appearance. The replay checks the flag immediately before each put; a put
already made when the token arrives cannot be recalled.

Declared without ``history`` (see ``shared.bus.liveness``): with it, the
liveliness query of the check made just after returned no tokens.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable, Iterator

import zenoh

from shared.bus import Bus
from shared.bus.keys import alive_key
from shared.errors import ServiceUnavailableError
from shared.lifecycle import Closes


class ServiceWatch(Closes):
    """Whether a service's token has appeared since this was built.

    Args:
        session: The replay's open session (close this first).
        namespace: The replay's namespace.
        service: The service watched (``bridge``, ``decide``).
        keys: The recorded keys it would take, sent or not (for the error).
        on_appear: Called once, on Zenoh's thread, when the token first
            appears, e.g. to wake the replay's wait (it must not block).

    Attributes:
        service: As given.
        keys: As given.
        appeared: Set on the token's first appearance; never cleared (a
            service that came and went may come back).
    """

    def __init__(
        self,
        session: zenoh.Session,
        namespace: str,
        service: str,
        keys: list[str],
        on_appear: Callable[[], None] = lambda: None,
    ) -> None:
        self.service = service
        self.keys = keys
        self.appeared = threading.Event()
        self._on_appear = on_appear
        self._lock = threading.Lock()
        self._subscriber = session.liveliness().declare_subscriber(
            alive_key(namespace, service), self._on_sample
        )

    def _on_sample(self, sample: zenoh.Sample) -> None:
        if sample.kind != zenoh.SampleKind.PUT:
            return
        with self._lock:
            first = not self.appeared.is_set()
            self.appeared.set()
        if first:
            self._on_appear()

    def close(self) -> None:
        """Stop watching (before the session closes)."""
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]


@contextlib.contextmanager
def service_watches(
    bus: Bus, guarded: dict[str, list[str]], stop: threading.Event
) -> Iterator[list[ServiceWatch]]:
    """A watch for each service of ``guarded`` with keys to send.

    Args:
        bus: The replay's open bus.
        guarded: Service -> the recorded keys to send that a live one would
            take (empty: not watched).
        stop: Set at a service's first sight: it wakes the replay's wait at
            once.

    The watches are undeclared on leaving, before the session closes.
    """
    namespace = bus.config.namespace
    with contextlib.ExitStack() as stack:
        yield [
            stack.enter_context(
                ServiceWatch(bus.session, namespace, service, keys, stop.set)
            )
            for service, keys in guarded.items()
            if keys
        ]


def appeared(watches: list[ServiceWatch]) -> ServiceWatch | None:
    """The first of ``watches`` whose service has come alive, if any."""
    return next((watch for watch in watches if watch.appeared.is_set()), None)


def service_alive(bus: Bus, service: str, keys: list[str]) -> bool:
    """Whether ``service``'s liveliness token is on the router now.

    Args:
        bus: The replay's open bus.
        service: The service's name (``bridge``, ``decide``).
        keys: The recorded keys a live one would take (for the error).

    Raises:
        ServiceUnavailableError: if the router did not answer within the
            bus ``timeout`` (no answer must not read as "not alive").
    """
    namespace = bus.config.namespace
    timeout = bus.config.timeout
    replies = list(
        bus.session.liveliness().get(alive_key(namespace, service), timeout=timeout)
    )
    alive = any(reply.ok is not None for reply in replies)
    if not alive and replies:  # only Zenoh's "Timeout": no answer
        article = "an" if service[0] in "aeiou" else "a"
        raise ServiceUnavailableError(
            "router",
            reason=f"it did not answer within {timeout:g} s whether {article} "
            f"{service} is alive in namespace {namespace!r}, and a replay of the "
            f"recorded {', '.join(keys)} is refused while one is; nothing was "
            "sent. To replay on purpose, choose the keys with --keys",
        )
    return alive
