"""The "alive elsewhere" hint of a call never outlasts the call's timeout.

The caller's error for a service without a token asks the router where else
the service is alive, with the hint's own 0.5 s (``HINT_TIMEOUT``), however
little of the call's timeout was left: a call given 1 ms could take half a
second, and a planner stage under its caller's deadline answer late. Now the
hint is asked only within the call's timeout, and left out once it has
gone. A real router and a real session holding ik's token elsewhere.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from test_alive_elsewhere import OTHER, REQUEST, hold_token

from armplan.launch import free_endpoint
from shared.bus import Bus, BusConfig, open_router
from shared.bus.routes import IK_SOLVE
from shared.errors import ServiceUnavailableError

#: A timeout already gone once the token has been looked for [s].
SPENT = 1e-9


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace="lab2")
    with open_router(config):
        yield config


@pytest.fixture(scope="module")
def ik_elsewhere(config: BusConfig) -> Iterator[None]:
    with Bus.connect(config) as bus:
        token = hold_token(bus, OTHER, "ik")
        yield
        token.undeclare()  # type: ignore[no-untyped-call]


def test_with_time_left_the_hint_is_there(
    config: BusConfig, ik_elsewhere: None
) -> None:
    with Bus.connect(config) as bus, pytest.raises(ServiceUnavailableError) as caught:
        bus.call(IK_SOLVE, REQUEST, timeout=5.0)
    assert caught.value.elsewhere == {"ik": [OTHER]}


def test_a_spent_timeout_leaves_the_hint_out(
    config: BusConfig, ik_elsewhere: None
) -> None:
    with Bus.connect(config) as bus, pytest.raises(ServiceUnavailableError) as caught:
        bus.call(IK_SOLVE, REQUEST, timeout=SPENT)
    assert caught.value.elsewhere == {}
    assert "lab2/alive/ik" in caught.value.message
