"""The "no router" error names only options the failing command has.

It ended with ``--zenoh-config for --remote`` for every command, even
``armplan stop`` (``--config``, no ``--remote``), and told ``armplan up``
and ``demo`` (no ``--connect``) to give the router's address with
``--connect``.
"""

from __future__ import annotations

import pytest
from armplan_cli import armplan

from armplan.launch import free_endpoint
from shared.bus import Bus, load_config
from shared.errors import ServiceUnavailableError
from shared.offered_options import offered, offering


def test_stop_names_its_config_option_and_not_remote() -> None:
    done = armplan("stop", "--connect", free_endpoint())
    assert done.returncode == 1
    assert "no Zenoh router answers" in done.stderr
    assert done.stderr.endswith(
        "give the client file `armplan certs` wrote (--config DIR/client.json5)\n"
    )
    assert "--remote" not in done.stderr
    assert "--zenoh-config" not in done.stderr


def test_plan_remote_names_its_zenoh_config_option() -> None:
    done = armplan(
        "plan", "--connect", free_endpoint(), "--target", "0.12", "-0.13", "0.05"
    )
    assert done.returncode == 1
    assert "or give the router's address with --connect" in done.stderr
    assert done.stderr.endswith(
        "give the client file `armplan certs` wrote (--zenoh-config DIR/client.json5)\n"
    )
    assert "--config " not in done.stderr


def unavailable(endpoint: str) -> str:
    """The message of a client's failure to reach a router at ``endpoint``."""
    with pytest.raises(ServiceUnavailableError) as raised:
        Bus.connect(load_config(endpoints=(endpoint,))).close()
    return raised.value.message


def test_a_command_without_connect_is_not_told_to_use_it() -> None:
    """``armplan up`` and ``demo`` offer ``--config`` only."""
    with offering({"--config", "--help"}):
        message = unavailable(free_endpoint())
    assert "--connect" not in message
    assert message.endswith("(--config DIR/client.json5)")


def test_a_process_offers_config_and_connect_unless_told() -> None:
    """What ``python -m`` services have; ``offering`` restores it after."""
    with offering({"--zenoh-config"}):
        pass
    assert offered() == {"--config", "--connect"}
    message = unavailable(free_endpoint())
    assert "or give the router's address with --connect" in message
