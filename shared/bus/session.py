"""Open Zenoh sessions: a router, or a client connected to the router.

:func:`has_router` says whether a client is connected to a router now,
:func:`has_router_or_peer` whether it is connected to anyone who may receive
what it puts.
"""

from __future__ import annotations

import threading
import time

import zenoh

from shared.bus.config import BusConfig
from shared.bus.left_open import held
from shared.bus.named_files import check_named_files
from shared.bus.secured import secured_settings
from shared.bus.zenoh_config import client_config, router_config
from shared.errors import BusConfigError, ServiceUnavailableError
from shared.offered_options import config_option, offered

#: Pause between attempts to reach the router [s].
RETRY_EVERY = 0.1


def open_client(
    config: BusConfig, wait: float = 0.0, stop: threading.Event | None = None
) -> zenoh.Session:
    """A client session connected to the router.

    Args:
        config: The bus settings (router endpoints).
        wait: How long to keep trying while no router answers [s]; 0 tries once.
        stop: Set when the process is asked to stop: the wait ends at once
            (a process still waiting for its router obeys SIGTERM).

    Raises:
        BusConfigError: if a file the configuration names (the CA certificate)
            is missing or unreadable.
        ServiceUnavailableError: naming the router's endpoints if none answers,
            or if ``stop`` was set before one did.
    """
    check_named_files(client_config(config), config)
    stop = stop or threading.Event()
    deadline = time.monotonic() + wait
    while True:
        try:
            return held(zenoh.open(client_config(config)))  # see left_open
        except zenoh.ZError as error:
            if time.monotonic() + RETRY_EVERY > deadline or stop.wait(RETRY_EVERY):
                raise ServiceUnavailableError(
                    "router", reason=_why_none(config, error, stop.is_set())
                ) from None


def has_router(session: zenoh.Session) -> bool:
    """Whether ``session`` (a client) is connected to a router now.

    Zenoh reconnects a client by itself once the router is back; in between,
    what the client publishes reaches nobody and it receives nothing. About
    2.5 us a call (a put with no subscriber: 4.6 us), cheap enough to ask
    before every put.
    """
    return bool(session.info.routers_zid())


def has_router_or_peer(session: zenoh.Session) -> bool:
    """Whether ``session`` (a client) is connected to a router or a peer now.

    A client may connect to a peer-mode session that listens on its endpoint
    (SPEC: peers with explicit connects), which receives what the client
    puts; :func:`has_router` does not count it, as ``routers_zid`` lists
    routers only. One more call (``peers_zid``) when no router is connected.
    """
    info = session.info
    return bool(info.routers_zid() or info.peers_zid())


def _why_none(config: BusConfig, error: zenoh.ZError, stopped: bool) -> str:
    """The reason no client session opened, for ``ServiceUnavailableError``."""
    where = ", ".join(config.endpoints)
    if stopped:
        return f"asked to stop while waiting for the Zenoh router at {where}"
    return f"no Zenoh router answers at {where} ({_short(error)}){_what_to_do(config)}"


def _what_to_do(config: BusConfig) -> str:
    """The causes to check and the router to start, for the client's error.

    Zenoh tells a refused login or certificate no differently from no router
    at all, so a secured client (TLS endpoints, a login) names both; and
    ``armplan up`` runs only the unsecured router. An unsecured client is
    refused just as silently by a secured router on its port (which ``armplan
    up`` cannot replace: the port is taken), so it names that too. The hint
    names only options the running command has (``shared.offered_options``).
    """
    connect = "--connect" in offered()
    if not secured_settings(config):
        return (
            "; start one with `armplan up`"
            + (", or give the router's address with --connect" if connect else "")
            + ". If a secured router (TLS) is there, it refuses this unsecured "
            f"client: give the client file `armplan certs` wrote ({_client_file()})"
        )
    return (
        f", or one answers but refuses this client: check the user, password "
        f"and certificate settings of {config.source} (the router's certificate "
        "must name the endpoint's host: `armplan certs --host`, and not have "
        "expired: the router logs an ERROR then), and the "
        "router's log; start the secured router with `python -m "
        "shared.bus.router --config DIR/router.json5`"
        + (", or give its address with --connect" if connect else "")
    )


def _client_file() -> str:
    """How the running command is given the client file (its own option)."""
    option = config_option()
    return "DIR/client.json5" if option is None else f"{option} DIR/client.json5"


def open_router(config: BusConfig, zid: str | None = None) -> zenoh.Session:
    """A router session listening on ``config.endpoints`` only.

    ``zid``: its Zenoh id (hex); default a random one.

    Raises:
        BusConfigError: if a file it names (certificate, key, passwords) is
            missing or unreadable, or it cannot listen there (port in use, bad
            address, a key that does not match its certificate).
    """
    check_named_files(router_config(config, zid), config)
    try:
        return zenoh.open(router_config(config, zid))
    except zenoh.ZError as error:
        raise BusConfigError(
            f"cannot listen on {', '.join(config.endpoints)} ({_short(error)})"
            f"{_router_hint(str(error))}",
            source=config.endpoints_from or config.source,
            setting="listen/endpoints",
        ) from None


def _router_hint(error: str) -> str:
    """What to check for Zenoh's reason not to open the router, or ``""``."""
    if "in use" in error.lower():
        return "; is another router using it?"
    if "KeyMismatch" in error:
        return (
            "; the router's key does not belong to its certificate: rerun "
            "`armplan certs --out DIR`, which writes both"
        )
    return ""


def _short(error: Exception) -> str:
    """Zenoh's message without its source location."""
    return " ".join(str(error).split(" at /")[0].split())
