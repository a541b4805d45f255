"""Zenoh configurations for the router and for every other armplan process.

Both always switch multicast scouting off and name their endpoints: the
router listens on exactly the configured endpoints (Zenoh's own default would
listen on every interface), clients connect to exactly those.
"""

from __future__ import annotations

import json

import zenoh

from shared.bus.config import BusConfig
from shared.errors import BusConfigError

#: How long a client waits for the router's handshake [ms]; Zenoh's default
#: of 10 s makes a wrong port (something else listening) a long hang.
OPEN_TIMEOUT_MS = 3000
_NO_SCOUTING = (
    ("scouting/multicast/enabled", "false"),
    ("scouting/gossip/enabled", "false"),
)


def router_config(bus: BusConfig, zid: str | None = None) -> zenoh.Config:
    """The router's Zenoh config: the file, listening on ``bus.endpoints`` only.

    ``zid``: the router's Zenoh id (hex), so that whoever started it can
    tell it from another router on the same port; default Zenoh's random one.
    """
    config = (
        zenoh.Config()
        if bus.router_text is None
        else zenoh.Config.from_json5(bus.router_text)
    )
    if zid is not None:
        _insert(config, "id", json.dumps(zid), bus)
    _insert(config, "mode", '"router"', bus)
    _insert(config, "listen/endpoints", json.dumps(list(bus.endpoints)), bus)
    for key, value in _NO_SCOUTING:
        _insert(config, key, value, bus)
    return config


def client_config(bus: BusConfig) -> zenoh.Config:
    """A client's Zenoh config: connects to the router, listens nowhere.

    ``bus.client_settings`` apply on top of armplan's client defaults (the
    handshake timeout), but cannot change the mode, the endpoints or scouting.
    """
    config = zenoh.Config()
    _insert(config, "transport/unicast/open_timeout", str(OPEN_TIMEOUT_MS), bus)
    for key, value in bus.client_settings:  # the rules below win over these
        _insert(config, key, value, bus)
    _insert(config, "mode", '"client"', bus)
    _insert(config, "connect/endpoints", json.dumps(list(bus.endpoints)), bus)
    _insert(config, "listen/endpoints", "[]", bus)
    for key, value in _NO_SCOUTING:
        _insert(config, key, value, bus)
    return config


def _insert(config: zenoh.Config, key: str, value: str, bus: BusConfig) -> None:
    try:
        config.insert_json5(key, value)
    except zenoh.ZError as error:
        problem = " ".join(str(error).split())
        raise BusConfigError(
            f"Zenoh refuses {value}: {problem}", source=bus.source, setting=key
        ) from None
