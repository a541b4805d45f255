"""Endpoints a router cannot listen on together: one socket, spelt twice.

``tcp/127.0.0.1:7447`` and ``tcp/localhost:7447`` are one socket, and so are
``tcp/...:7447`` and ``tls/...:7447`` (both TCP): a router given both
clashes with itself ("Address already in use"), which reads as another
router on the port. Endpoints are compared by transport (TCP for tcp, tls
and ws; UDP for udp and quic), port and the addresses their host resolves
to (``localhost`` is ``127.0.0.1``, and often ``::1`` too).
"""

from __future__ import annotations

import socket
from functools import cache

from shared.bus.config import ENDPOINT_SYNTAX

#: The transport under each Zenoh protocol.
TRANSPORT = {"tcp": "tcp", "tls": "tcp", "ws": "tcp", "udp": "udp", "quic": "udp"}


@cache
def addresses(host: str) -> frozenset[str]:
    """The addresses ``host`` names (itself if it does not resolve)."""
    bare = host.removeprefix("[").removesuffix("]")
    try:
        found = socket.getaddrinfo(bare, None, proto=socket.IPPROTO_TCP)
    except (OSError, UnicodeError):
        return frozenset({bare})
    return frozenset(str(info[4][0]) for info in found) or frozenset({bare})


def clashes(endpoints: list[str]) -> list[tuple[str, str]]:
    """Each pair of ``endpoints`` (in order) that is one socket.

    Malformed endpoints are left to ``config.check_endpoint``.
    """
    found = []
    for i, first in enumerate(endpoints):
        for second in endpoints[i + 1 :]:
            if _one_socket(first, second):
                found.append((first, second))
    return found


def _one_socket(first: str, second: str) -> bool:
    """Whether two endpoints are one socket (hosts resolved only if it may be)."""
    a, b = ENDPOINT_SYNTAX.match(first), ENDPOINT_SYNTAX.match(second)
    if a is None or b is None:
        return False
    if (TRANSPORT[a[1]], int(a[3])) != (TRANSPORT[b[1]], int(b[3])):
        return False
    return a[2] == b[2] or bool(addresses(a[2]) & addresses(b[2]))
