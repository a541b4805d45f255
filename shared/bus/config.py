"""armplan's Zenoh settings: where the router is, the namespace, the limits.

One JSON5 file configures every process (``config/zenoh.json5``): it is the
router's Zenoh configuration, and armplan's own settings ride in its
``metadata.armplan`` section, which Zenoh carries without reading. Services
and clients connect to the router's ``listen`` endpoints in client mode.
:class:`BusConfig` is that file, validated; ``config_file.py`` reads it and
``zenoh_config.py`` turns it into Zenoh configurations.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

from shared.bus.keys import check_path
from shared.errors import BusConfigError, InvalidInputError
from shared.every_interface import names_every_interface

#: The router's endpoint unless configured otherwise: loopback only.
DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"
#: Key prefix of every armplan key expression.
DEFAULT_NAMESPACE = "armplan"
#: Largest request payload a service accepts [bytes] (16 MiB).
DEFAULT_MAX_PAYLOAD = 16 * 1024 * 1024
#: How long a client waits for a reply [s].
DEFAULT_TIMEOUT = 5.0
#: How long a caller waits for a repeatable route's answer before asking again [s].
DEFAULT_RESEND_AFTER = 1.0
#: Longest ``timeout`` and ``resend_after`` [s]: a day. A caller never waits
#: longer (``caller.py`` clamps its waits to it); a longer one crashed every
#: call (an ``OverflowError`` past ``threading.TIMEOUT_MAX``, a "negative
#: timeout" of Zenoh's) instead of being refused at start.
MAX_WAIT = 86_400.0
#: Threads per service answering queries.
DEFAULT_WORKERS = 4
#: Requests a service lets wait before it answers ``service_busy``.
DEFAULT_QUEUE_LIMIT = 256

ENDPOINT_SYNTAX = re.compile(
    r"^(tcp|tls|udp|quic|ws)/(\[[0-9a-fA-F:.]+\]|[^\s/:\[\]]+):(\d+)$"
)


def check_endpoint(endpoint: str, source: str) -> str:
    """``endpoint`` if it reads ``PROTO/HOST:PORT`` (e.g. ``tcp/127.0.0.1:7447``).

    The host must be one interface's address or a name, never the
    unspecified (all-zero) address of IPv4 or IPv6: a router listening there
    is open on every network the machine is on, the robot's included.

    Raises:
        BusConfigError: naming ``source`` (file or option) and the endpoint.
    """
    match = ENDPOINT_SYNTAX.match(endpoint)
    if not match:
        raise BusConfigError(
            f"endpoint {endpoint!r} must read PROTO/HOST:PORT, e.g. {DEFAULT_ENDPOINT}",
            source=source,
            setting="endpoint",
        )
    if names_every_interface(match.group(2)):
        raise BusConfigError(
            f"endpoint {endpoint!r} names every interface: give the address of "
            "the one the other processes or machines reach (127.0.0.1 on one "
            "machine)",
            source=source,
            setting="endpoint",
        )
    if not 0 < int(match.group(3)) < 65536:
        raise BusConfigError(
            f"endpoint {endpoint!r}: port {int(match.group(3))} is outside 1..65535",
            source=source,
            setting="endpoint",
        )
    return endpoint


@dataclass(frozen=True)
class BusConfig:
    """armplan's bus settings, validated.

    Attributes:
        endpoints: The router's endpoints: where it listens, where the others
            connect, e.g. ``("tcp/127.0.0.1:7447",)``.
        namespace: Prefix of every key, e.g. ``"armplan"`` (``armplan/plan``).
        max_payload: Largest request payload a service accepts [bytes].
        timeout: How long a client waits for a reply by default [s], at
            most ``MAX_WAIT``.
        resend_after: How long a caller waits for the answer of a repeatable
            route before it asks once more [s] (``Route.repeatable``), at
            most ``MAX_WAIT``.
        workers: Threads per service answering queries.
        queue_limit: Requests waiting per service before ``service_busy``.
        client_settings: Zenoh settings for client sessions as (path, JSON
            value) pairs, e.g. ``("transport/auth/usrpwd/user", '"planner"')``.
        source: Where the settings came from (file path or "built-in defaults").
        router_text: The file's JSON5 text, the base of the router's config, or
            ``None`` for the built-in defaults.
        endpoints_from: The option the endpoints came from
            (``with_endpoints``), or ``""`` if from ``source``.
        namespace_from: The option the namespace came from
            (``--namespace``), or ``""`` if from ``source`` (which stays
            the file's name: :attr:`file`, its secrets' check).
    """

    endpoints: tuple[str, ...] = (DEFAULT_ENDPOINT,)
    namespace: str = DEFAULT_NAMESPACE
    max_payload: int = DEFAULT_MAX_PAYLOAD
    timeout: float = DEFAULT_TIMEOUT
    resend_after: float = DEFAULT_RESEND_AFTER
    workers: int = DEFAULT_WORKERS
    queue_limit: int = DEFAULT_QUEUE_LIMIT
    client_settings: tuple[tuple[str, str], ...] = ()
    source: str = "built-in defaults"
    router_text: str | None = None
    endpoints_from: str = ""
    namespace_from: str = ""

    def __post_init__(self) -> None:
        if not self.endpoints:
            raise BusConfigError(
                "needs at least one router endpoint", source=self.source
            )
        for endpoint in self.endpoints:
            check_endpoint(endpoint, self.source)
        try:
            check_path(self.namespace, "namespace")
        except InvalidInputError as error:
            given = f" + {self.namespace_from}" if self.namespace_from else ""
            raise BusConfigError(
                error.message, source=f"{self.source}{given}", setting="namespace"
            ) from None
        self._check_positive("max_payload", self.max_payload)
        self._check_wait("timeout", self.timeout)
        self._check_wait("resend_after", self.resend_after)
        self._check_positive("workers", self.workers)
        self._check_positive("queue_limit", self.queue_limit)

    def _check_positive(self, name: str, value: float) -> None:
        if not value > 0:
            raise BusConfigError(
                f"{name} must be positive, got {value}",
                source=self.source,
                setting=f"metadata/armplan/{name}",
            )

    def _check_wait(self, name: str, value: float) -> None:
        self._check_positive(name, value)
        if value > MAX_WAIT:
            raise BusConfigError(
                f"{name} must be at most {MAX_WAIT:g} s (a day), got {value:g}",
                source=self.source,
                setting=f"metadata/armplan/{name}",
            )

    def with_endpoints(self, endpoints: tuple[str, ...], source: str) -> BusConfig:
        """The same settings with other router endpoints (``--listen``/``--connect``).

        Args:
            endpoints: The endpoints, e.g. ``("tcp/127.0.0.1:7448",)``.
            source: The option they came from, for error messages.
        """
        for endpoint in endpoints:
            check_endpoint(endpoint, source)
        return replace(self, endpoints=tuple(endpoints), endpoints_from=source)

    @property
    def file(self) -> str | None:
        """The file the settings came from, ``None`` for the built-in defaults."""
        return None if self.router_text is None else self.source

    @property
    def endpoint(self) -> str:
        """The first router endpoint (for messages)."""
        return self.endpoints[0]

    @property
    def tls(self) -> bool:
        """Whether the router is reached over TLS (the secured set)."""
        return any(e.startswith("tls/") for e in self.endpoints)
