"""Whether a configuration belongs to the secured set, and by which settings.

A file is secured if its router endpoints use TLS, or if it sets a login,
TLS files or access control, for a client (``metadata.armplan.client``) or
for the router (the file's own Zenoh settings). ``armplan up`` and ``armplan
demo`` refuse such a file (they run the unsecured set, every process with
one file); the router logs its handshakes when secured; a client names the
login and certificate settings when no session opens.
"""

from __future__ import annotations

import json

import zenoh

from shared.bus.config import BusConfig
from shared.bus.named_files import named_files
from shared.bus.zenoh_config import client_config, router_config

#: Settings that make a configuration secured when they hold a value.
_SECURING = (
    "transport/auth/usrpwd/user",
    "transport/auth/usrpwd/password",
    "transport/auth/usrpwd/dictionary_file",
)


def secured_settings(config: BusConfig) -> list[str]:
    """The settings that make ``config`` secured, in order; empty if none.

    E.g. ``["listen/endpoints", "transport/auth/usrpwd/user",
    "transport/link/tls/root_ca_certificate"]`` for a client file of
    ``armplan certs``.
    """
    found = ["listen/endpoints"] if config.tls else []
    for zenoh_config in (client_config(config), router_config(config)):
        found += [s for s in _SECURING if _value(zenoh_config, s) is not None]
        found += list(named_files(zenoh_config))
        if _value(zenoh_config, "access_control/enabled") is True:
            found.append("access_control/enabled")
    return list(dict.fromkeys(found))


def _value(config: zenoh.Config, setting: str) -> object:
    """The setting's value, ``None`` if it is unset (or null)."""
    try:
        return json.loads(config.get_json(setting))
    except zenoh.ZError:
        return None
