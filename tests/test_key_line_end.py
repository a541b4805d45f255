"""A namespace or service name ending in a line end is refused, not passed on.

``check_path`` and ``check_name`` matched with ``$``, which also matches
before a final ``\\n``: ``--namespace $'lab\\n'`` was taken, and a token
``lab1\\n/alive/bridge`` held on the router by anyone put a raw line end
into another process's "not alive" error (``(--namespace lab1\\n)``). A
real router, a real session holding that token.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from test_alive_elsewhere import hold_token

from armplan.launch import free_endpoint
from shared.bus import Bus, BusConfig, open_router
from shared.bus.keys import check_name, check_path
from shared.bus.options import with_namespace
from shared.errors import BusConfigError, InvalidInputError


@pytest.mark.parametrize("text", ["lab\n", "lab/nao1\n", "ik\n"])
def test_a_final_line_end_is_no_chunk(text: str) -> None:
    with pytest.raises(InvalidInputError):
        check_path(text, "namespace")
    with pytest.raises(InvalidInputError):
        check_name(text)


def test_namespace_option_with_a_line_end_is_refused() -> None:
    with pytest.raises(BusConfigError, match="--namespace"):
        with_namespace(BusConfig(), "lab2\n")


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace="lab2")
    with open_router(config):
        yield config


def test_a_token_key_with_a_line_end_is_no_namespace(config: BusConfig) -> None:
    with Bus.connect(config) as other, Bus.connect(config) as bus:
        token = hold_token(other, "lab1\n", "bridge")
        try:
            error = bus.not_alive(["bridge"], 0.1)
        finally:
            token.undeclare()
    assert error.elsewhere == {}
    assert "\n" not in error.message
