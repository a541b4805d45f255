"""Free loopback endpoints, so parallel runs never collide on a port."""

from __future__ import annotations

import socket


def free_endpoint(host: str = "127.0.0.1") -> str:
    """A TCP endpoint on ``host`` whose port is free now, e.g. ``tcp/127.0.0.1:40123``.

    The port is found by binding port 0 and reading what the system chose.
    """
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind((host, 0))
        port = probe.getsockname()[1]
    return f"tcp/{host}:{port}"
