"""Open Zenoh sessions: a router, or a client connected to the router."""

from __future__ import annotations

import time

import zenoh

from shared.bus.config import BusConfig
from shared.bus.zenoh_config import client_config, router_config
from shared.errors import BusConfigError, ServiceUnavailableError

#: Pause between attempts to reach the router [s].
RETRY_EVERY = 0.1


def open_client(config: BusConfig, wait: float = 0.0) -> zenoh.Session:
    """A client session connected to the router.

    Args:
        config: The bus settings (router endpoints).
        wait: How long to keep trying while no router answers [s]; 0 tries once.

    Raises:
        ServiceUnavailableError: naming the router's endpoints if none answers.
    """
    deadline = time.monotonic() + wait
    while True:
        try:
            return zenoh.open(client_config(config))
        except zenoh.ZError as error:
            if time.monotonic() + RETRY_EVERY > deadline:
                raise ServiceUnavailableError(
                    "router",
                    reason=f"no Zenoh router answers at {', '.join(config.endpoints)} "
                    f"({_short(error)}){_secured_hint(config)}; start one with "
                    "`armplan up`, or give the router's address with --connect",
                ) from None
            time.sleep(RETRY_EVERY)


def _secured_hint(config: BusConfig) -> str:
    """The second cause to name for a secured connection, or ``""``.

    Zenoh tells a refused login or certificate no differently from no router
    at all, so a client with TLS endpoints or a login names both.
    """
    secured = config.tls or any(
        path.startswith("transport/auth") for path, _ in config.client_settings
    )
    if not secured:
        return ""
    return (
        f", or one answers but refuses this client: check the user, password "
        f"and certificate settings of {config.source}"
    )


def open_router(config: BusConfig, zid: str | None = None) -> zenoh.Session:
    """A router session listening on ``config.endpoints`` only.

    ``zid``: its Zenoh id (hex); default a random one.

    Raises:
        BusConfigError: if it cannot listen there (port in use, bad address).
    """
    try:
        return zenoh.open(router_config(config, zid))
    except zenoh.ZError as error:
        raise BusConfigError(
            f"cannot listen on {', '.join(config.endpoints)} ({_short(error)}); "
            "is another router using it?",
            source=config.source,
            setting="listen/endpoints",
        ) from None


def _short(error: Exception) -> str:
    """Zenoh's message without its source location."""
    return " ".join(str(error).split(" at /")[0].split())
