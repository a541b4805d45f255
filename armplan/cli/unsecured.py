"""``armplan up`` and ``armplan demo`` run the unsecured set only: the checks.

Both start a router and every process with one configuration file, while the
secured router lets each process in with its own user's file
(docs/services.md, "Security"). Given a secured file they started a plain
router (``--listen tcp/...`` replaced the file's TLS endpoint, and the demo
did not check at all), and the services then waited a minute to log in and
failed as if no router answered. Both now refuse, before anything starts, a
file secured by its own endpoints or by its login, TLS or access control
settings, and a TLS ``--listen``. They also refuse a router endpoint other
than ``tcp/`` (``udp/`` was taken, and the demo then failed at random).
"""

from __future__ import annotations

from collections.abc import Sequence

from shared.bus import BusConfig
from shared.bus.config import check_endpoint
from shared.bus.secured import secured_settings
from shared.errors import InvalidInputError

#: Protocols that need certificates: the secured set's.
SECURED_PROTOCOLS = ("tls/", "quic/")
#: The one protocol the unsecured router listens on.
PLAIN_PROTOCOL = "tcp/"


def check_unsecured(config: BusConfig, command: str) -> None:
    """Refuse ``config`` (the file as read, before ``--listen``) if it is secured.

    Raises:
        InvalidInputError: naming the file and the settings that secure it.
    """
    settings = secured_settings(config)
    if settings:
        raise InvalidInputError(
            f"{config.source} is a secured configuration ({', '.join(settings)}): "
            f"armplan {command} runs the unsecured set, every process with the "
            "one file, while the secured router lets each process in with its "
            "own user's file only; run the secured set process by process, each "
            "with its own file (docs/services.md, 'Security')",
            field="config",
        )


def check_plain_listen(
    endpoints: Sequence[str], command: str, source: str = "--listen"
) -> None:
    """Refuse a router endpoint other than ``tcp/``: TLS (the secured set's), UDP...

    Args:
        endpoints: The router's endpoints.
        command: ``"up"`` or ``"demo"``, for the message.
        source: Where they come from, for the message: ``--listen``, or the
            configuration file (``"FILE endpoint"``).

    Raises:
        BusConfigError: an endpoint that does not read ``PROTO/HOST:PORT``
            (checked first: ``127.0.0.1:7447`` has no protocol to name).
        InvalidInputError: naming the endpoint and why only ``tcp/`` is taken.
    """
    for endpoint in endpoints:
        check_endpoint(endpoint, source)
        if endpoint.startswith(SECURED_PROTOCOLS):
            raise InvalidInputError(
                f"{source} {endpoint}: armplan {command} runs the unsecured "
                "router, which listens on tcp/ (e.g. tcp/127.0.0.1:7447); a TLS "
                "router needs certificates and a login per process: `armplan "
                "certs --out DIR`, then the secured set process by process "
                "(docs/services.md, 'Security')",
                field="listen",
            )
        if not endpoint.startswith(PLAIN_PROTOCOL):
            protocol = endpoint.split("/", 1)[0]
            raise InvalidInputError(
                f"{source} {endpoint}: armplan {command} runs its router on tcp/ "
                f"only (e.g. tcp/127.0.0.1:7447): the services' calls need its "
                f"reliable, ordered stream, which {protocol}/ is not (over udp/ "
                "a demo's call to the bridge was lost and the run failed)",
                field="listen",
            )
