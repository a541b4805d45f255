"""Which listen endpoints are one socket (``shared.bus.listen_clash``)."""

from __future__ import annotations

import pytest

from shared.bus.listen_clash import addresses, clashes


def test_localhost_resolves_to_loopback() -> None:
    """The premise: this machine's ``localhost`` names 127.0.0.1."""
    assert "127.0.0.1" in addresses("localhost")


@pytest.mark.parametrize(
    ("first", "second"),
    [
        ("tcp/127.0.0.1:7447", "tcp/localhost:7447"),
        ("tcp/127.0.0.1:7447", "tls/127.0.0.1:7447"),  # both TCP
        ("udp/127.0.0.1:7447", "quic/localhost:7447"),  # both UDP
        ("tcp/[::1]:7447", "tcp/[::1]:7447"),
    ],
)
def test_one_socket_spelt_twice_clashes(first: str, second: str) -> None:
    assert clashes([first, "tcp/127.0.0.1:1", second]) == [(first, second)]


@pytest.mark.parametrize(
    "endpoints",
    [
        ["tcp/127.0.0.1:7447", "tcp/127.0.0.1:7448"],  # other port
        ["tcp/127.0.0.1:7447", "udp/127.0.0.1:7447"],  # other transport
        ["tcp/127.0.0.1:7447", "tcp/127.0.0.2:7447"],  # other address
        ["tcp/127.0.0.1:7447", "not an endpoint"],  # left to check_endpoint
    ],
)
def test_different_sockets_do_not_clash(endpoints: list[str]) -> None:
    assert clashes(endpoints) == []
