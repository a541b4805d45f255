"""Whether a listening address names every interface of the machine.

The unspecified (all-zero) IPv4 or IPv6 address, given to a server, opens
it on every network the machine is on, the robot's included: armplan's
router endpoints (``shared.bus.config.check_endpoint``) and the simulated
NAO's address (``bridge.address.check_listen_url``) refuse it. The short
IPv4 spellings the system's resolver reads as the same address (``0``,
``0.0``, ``0x0``, ``000.000.000.000``) are refused as well.
"""

from __future__ import annotations

import ipaddress
import socket


def names_every_interface(host: str) -> bool:
    """Whether ``host`` is the unspecified IPv4 or IPv6 address, however spelt.

    Args:
        host: An address or a name; an IPv6 address may keep its brackets.
    """
    bare = host.strip("[]")
    try:
        return ipaddress.ip_address(bare).is_unspecified
    except ValueError:
        pass
    try:
        return socket.inet_aton(bare) == bytes(4)
    except OSError:  # a name, not an address
        return False
