"""The bus: one armplan process's Zenoh session, its settings, and what it can do.

A client opens a :class:`Bus` and calls routes; a service gets one to call the
services it needs and to publish. Example::

    with Bus.connect(load_config()) as bus:
        result = bus.call(IK_SOLVE, IKRequest(target=(0.12, -0.13, 0.05)))
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable
from typing import Any

import zenoh

from shared.bus.caller import (
    Check,
    answered,
    join_forwarders,
    read_reply,
    service_timing,
)
from shared.bus.config import BusConfig
from shared.bus.elsewhere import HINT_TIMEOUT, alive_elsewhere, not_alive_error
from shared.bus.gone_callers import GoneCallers
from shared.bus.keys import caller_key, service_key
from shared.bus.left_open import close as close_session
from shared.bus.liveness import QUERY_TIMEOUT, AliveServices, list_alive
from shared.bus.route import Rep, Req, Route
from shared.bus.session import open_client
from shared.bus.topics import droppable
from shared.errors import ServiceUnavailableError
from shared.lifecycle import Closes
from shared.messages import Message, ServiceTiming

#: Pause between liveliness checks while waiting for services [s].
WAIT_POLL = 0.05
#: Longest wait, on closing, for the reply readers of open queries [s].
FORWARDERS_GRACE = 2.0


class Bus(Closes):
    """An open client session with the project's settings.

    Attributes:
        session: The Zenoh session.
        config: The bus settings.
    """

    def __init__(self, session: zenoh.Session, config: BusConfig) -> None:
        self.session = session
        self.config = config
        self._alive = AliveServices(session, config.namespace)
        # Held while open: a service sees this caller's session end
        # (shared.bus.gone_callers); every query names the session.
        self._caller = session.liveliness().declare_token(
            caller_key(config.namespace, str(session.zid()))
        )
        self._gone: GoneCallers | None = None
        self._gone_lock = threading.Lock()

    @classmethod
    def connect(
        cls, config: BusConfig, wait: float = 0.0, stop: threading.Event | None = None
    ) -> Bus:
        """Connect to the router.

        Args:
            config: The bus settings.
            wait: How long to keep trying while no router answers [s].
            stop: Set when the process is asked to stop: the wait ends at once.

        Raises:
            ServiceUnavailableError: naming the router's endpoints if none
                answers, or if ``stop`` was set before one did.
        """
        session = open_client(config, wait, stop)
        try:
            return cls(session, config)
        except BaseException:  # Ctrl-C too: nothing else would close it
            close_session(session)
            raise

    def key(self, path: str) -> str:
        """The full key of ``path``, e.g. ``armplan/plan/trajectory``."""
        return service_key(self.config.namespace, path)

    def call(
        self,
        route: Route[Any, Rep],
        request: Message | str | bytes,
        *,
        timeout: float | None = None,
        repeat: bool | None = None,
        unseen: bool = False,
        check: Check | None = None,
    ) -> Rep:
        """Ask ``route``'s service; its typed reply, or its typed error raised.

        Args:
            route: The route, e.g. ``IK_SOLVE``.
            request: The request message (or raw JSON, sent as is).
            timeout: Longest wait [s]; default ``config.timeout``.
            repeat: Ask once more after ``config.resend_after`` without an
                answer; default ``route.repeatable``. Pass ``True`` only if
                asking twice is harmless (e.g. a plan with a ``request_id``).
            unseen: Ask even if the service's liveliness token is not seen
                (``armplan stop``); its absence is said only if no reply
                comes.
            check: Called about every half second while the answer is
                waited for; what it raises ends the wait and is raised here.

        Raises:
            ServiceUnavailableError: if the service is not running.
            RequestTimeoutError: if it does not answer in time.
            ArmplanError: the service's own error, rebuilt with its kind.
        """
        reply, wait = self._ask(route, request, timeout, repeat, unseen, check)
        return read_reply(route, reply, route.key(self.config.namespace), wait)

    def call_timed(
        self,
        route: Route[Any, Rep],
        request: Message | str | bytes,
        *,
        timeout: float | None = None,
    ) -> tuple[Rep, ServiceTiming | None]:
        """:meth:`call`, and where the request's time went in the service.

        The second item is ``None`` if the service did not say.
        """
        reply, wait = self._ask(route, request, timeout, None)
        key = route.key(self.config.namespace)
        return read_reply(route, reply, key, wait), service_timing(reply)

    def _ask(
        self,
        route: Route[Any, Any],
        request: Message | str | bytes,
        timeout: float | None,
        repeat: bool | None,
        unseen: bool = False,
        check: Check | None = None,
    ) -> tuple[zenoh.Reply, float]:
        """Zenoh's reply to ``request``, and the wait allowed [s]."""
        wait = self.config.timeout if timeout is None else timeout
        reply = answered(
            self.session,
            self._alive,
            self.config.namespace,
            route,
            request,
            wait,
            self.config.resend_after,
            route.repeatable if repeat is None else repeat,
            unseen,
            check,
        )
        return reply, wait

    def remote(self, route: Route[Req, Rep]) -> Callable[[Req], Rep]:
        """``route`` as a plain function, to hand to an algorithm that calls it."""

        def ask(request: Req) -> Rep:
            return self.call(route, request)

        return ask

    def publish(self, path: str, message: Message) -> None:
        """Put ``message``'s JSON on ``<namespace>/<path>``.

        With Zenoh's ``BLOCK`` congestion control, unless the topic is
        :attr:`~shared.bus.topics.Topic.droppable` (``bridge/state``): a
        congested link makes the put wait for room (at most Zenoh's
        ``wait_before_close``, 5 s by default, then the link is closed)
        instead of dropping it silently.
        """
        self.session.put(
            self.key(path),
            message.to_json(),
            encoding=zenoh.Encoding.APPLICATION_JSON,
            congestion_control=zenoh.CongestionControl.DROP
            if droppable(path)
            else zenoh.CongestionControl.BLOCK,
        )

    def caller_gone(self, session: str | None) -> bool:
        """Whether the caller whose session id is ``session`` has gone.

        Its caller token was seen removed: its session ended (interrupted or
        killed) since this bus first asked (:mod:`shared.bus.gone_callers`;
        the first call starts the watch). ``None`` (not said): False.
        """
        with self._gone_lock:
            if self._gone is None:
                self._gone = GoneCallers(self.session, self.config.namespace)
            gone = self._gone
        return gone.gone(session)

    def is_alive(self, service: str) -> bool:
        """Whether ``service`` holds its liveliness token (cached; fast)."""
        return self._alive.is_alive(service)

    def alive(self, timeout: float = QUERY_TIMEOUT) -> list[str]:
        """Names of the services running now, sorted.

        Args:
            timeout: Longest wait for the router's answer [s].
        """
        return list_alive(self.session, self.config.namespace, timeout)

    def wait_alive(
        self,
        services: Iterable[str],
        timeout: float,
        stop: threading.Event | None = None,
    ) -> list[str]:
        """Wait until every one of ``services`` is running.

        Args:
            services: Service names, e.g. ``["ik", "planner"]``.
            timeout: Longest wait [s].
            stop: Set when the process is asked to stop: the wait ends at once.

        Returns:
            The services still missing when it returned (empty: all alive).
        """
        stop = stop or threading.Event()
        deadline = time.monotonic() + timeout
        while True:
            left = max(deadline - time.monotonic(), WAIT_POLL)
            missing = sorted(set(services) - set(self.alive(min(QUERY_TIMEOUT, left))))
            if not missing or time.monotonic() >= deadline or stop.is_set():
                return missing
            stop.wait(min(WAIT_POLL, max(deadline - time.monotonic(), 0.0)))

    def alive_elsewhere(
        self, services: Iterable[str], timeout: float = HINT_TIMEOUT
    ) -> dict[str, list[str]]:
        """The other namespaces where each of ``services`` is alive (best effort).

        One short liveliness query per service, all within ``timeout`` [s]
        (none if it is 0 or less): ask only once a wait has failed. See
        :mod:`shared.bus.elsewhere`.
        """
        return alive_elsewhere(self.session, self.config.namespace, services, timeout)

    def not_alive(
        self, missing: list[str], waited: float, note: str = ""
    ) -> ServiceUnavailableError:
        """The error for ``missing`` after :meth:`wait_alive` waited ``waited`` [s].

        It names the token keys watched and where else the services are alive.
        """
        return not_alive_error(
            self.session, self.config.namespace, missing, waited, note
        )

    def close(self) -> None:
        """Close the session (after undeclaring what this bus declared).

        Then wait (up to ``FORWARDERS_GRACE``) for the threads that read
        replies of queries the session had open: see
        :func:`shared.bus.caller.join_forwarders`.
        """
        self._alive.close()
        with self._gone_lock:
            if self._gone is not None:
                self._gone.close()
        self._caller.undeclare()  # type: ignore[no-untyped-call]
        close_session(self.session)
        join_forwarders(self.session, FORWARDERS_GRACE)
