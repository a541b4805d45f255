"""Can the simulated NAO listen at an address? Asked before anything starts.

libqi reports a port in use or an address of another machine only once the
session tries to listen, in a long ``RuntimeError``; :func:`check_can_listen`
asks the operating system the same question first, with a socket bound the
way libqi (Boost.Asio, ``SO_REUSEADDR``) binds, and :func:`listen_failure`
turns libqi's own error into the same typed one.
"""

from __future__ import annotations

import re
import socket

from shared.errors import InvalidInputError

_BIND_REASON = re.compile(r"bind: ([^\[\n]+)")


def host_port(url: str) -> tuple[str, int]:
    """Host and port of a checked NAOqi address ``tcp://HOST:PORT``."""
    host, port = url.split("://", 1)[1].rsplit(":", 1)
    return host, int(port)


def check_can_listen(url: str) -> str:
    """``url`` if a server may listen there now; else InvalidInputError.

    Args:
        url: A checked NAOqi address ``tcp://HOST:PORT`` (port 0: any free one).

    Raises:
        InvalidInputError: naming the address and the reason, e.g. "Address
            already in use" or "Cannot assign requested address" (not a
            local address).
    """
    host, port = host_port(url)
    try:
        family, kind, proto, _, address = socket.getaddrinfo(
            host, port, type=socket.SOCK_STREAM
        )[0]
    except socket.gaierror as exc:
        raise cannot_listen(url, exc.strerror or str(exc)) from None
    with socket.socket(family, kind, proto) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind(address)
        except OSError as exc:
            raise cannot_listen(url, exc.strerror or str(exc)) from None
    return url


def listen_failure(url: str, error: Exception) -> InvalidInputError:
    """libqi's error on listening at ``url`` as a one-line typed error."""
    found = _BIND_REASON.search(str(error))
    reason = found.group(1).strip() if found else str(error).strip().splitlines()[-1]
    return cannot_listen(url, reason)


def cannot_listen(url: str, reason: str) -> InvalidInputError:
    """The error "cannot listen at URL: REASON" (field ``listen``)."""
    return InvalidInputError(
        f"cannot listen at {url}: {reason}", field="listen", url=url, reason=reason
    )
