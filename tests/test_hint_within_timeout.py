"""The "alive elsewhere" hint of a call never outlasts the call's timeout.

The caller's error for a service without a token asks the router where else
the service is alive, with the hint's own 0.5 s (``HINT_TIMEOUT``), however
little of the call's timeout was left: a call given 1 ms could take half a
second, and a planner stage under its caller's deadline answer late. Now the
hint is asked only within the call's timeout, and left out once it has
gone. A call whose time runs out before the router has said whether the
token is there is the call's timeout (``shared.bus.caller.answered``). A
real router and a real session holding ik's token elsewhere.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest
from test_alive_elsewhere import OTHER, REQUEST, hold_token
from test_planner_remote import PATH

from armplan.launch import free_endpoint
from services.planner.remote import RemoteStages
from shared.bus import Bus, BusConfig, open_router
from shared.bus.deadline import Due, serving_until
from shared.bus.routes import IK_SOLVE
from shared.errors import RequestTimeoutError, ServiceUnavailableError
from shared.messages import PlanRequest

#: A timeout gone before the token can be looked for [s].
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


def test_a_spent_timeout_is_the_calls_timeout_with_no_hint(
    config: BusConfig, ik_elsewhere: None
) -> None:
    """Spent before the router could say whether ik's token is there: the
    call's own timeout. Nothing was learnt of the token, so neither "no
    liveliness token" (CI saw a running fit service called absent so) nor
    the hint of where else ik runs."""
    with Bus.connect(config) as bus, pytest.raises(RequestTimeoutError) as caught:
        bus.call(IK_SOLVE, REQUEST, timeout=SPENT)
    assert caught.value.message == (
        "service 'ik' did not answer lab2/ik/solve within 0.000 s"
    )


def test_the_planners_check_keeps_the_hint_within_its_callers_time(
    config: BusConfig, ik_elsewhere: None
) -> None:
    """The planner's check of the stages it needs asked the hint its whole
    0.5 s whatever its caller had left; now only within that time (here
    already gone: no hint), and the whole hint with no caller's deadline."""
    request = PlanRequest(wrist_path=PATH, method="least-norm")  # needs ik only
    with Bus.connect(config) as bus:
        stages = RemoteStages(bus)
        with pytest.raises(ServiceUnavailableError) as free:
            stages.require(request)
        gone = Due(at=time.monotonic() - 1.0, budget=1.0)
        with serving_until(gone), pytest.raises(ServiceUnavailableError) as late:
            stages.require(request)
    assert free.value.elsewhere == {"ik": [OTHER]}
    assert late.value.elsewhere == {}
    assert "finds no liveliness token under lab2/alive/" in late.value.message
