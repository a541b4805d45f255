"""A request with many wrong parts is refused as fast as one with a few.

Finding the misspelt key (``shared.messages.base``) compared each missing
field with every other error: a ``bridge/execute`` request whose
trajectory held 4000 unknown objects (32 kB) kept a worker 15 s, four
times as many 16 times as long, so a few requests far under
``max_payload`` held every worker. And pydantic kept an error for each
wrong item of a list: 8 million wrong numbers (16 MB) took a service over
6 GB and minutes (``shared.messages.fail_fast``). A real router, a service
host serving the bridge's ``bridge/execute`` route (its parsing is the
host's, before any handler), a client calling it with raw bytes.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from armplan.launch import free_endpoint
from shared.bus import Bus, BusConfig, Endpoint, ServiceHost, open_router
from shared.bus.robot_routes import EXECUTE
from shared.errors import InvalidInputError
from shared.messages import ExecuteReply, ExecuteRequest

#: Unknown keys in one object: about 2.4 MB of JSON, 14 s of work before.
KEYS = 200_000
#: Wrong items in one list.
ITEMS = 200_000
#: Unknown keys of LONG_KEY characters in one object: 4.8 MB of JSON, 13 s
#: of difflib before keys that long were left out of the search.
LONG_KEYS, LONG_KEY = 600, 8000


def refuse(request: ExecuteRequest) -> ExecuteReply:
    """The handler: never reached by an invalid request."""
    raise InvalidInputError("not played in this test", field="trajectory")


@pytest.fixture(scope="module")
def client() -> Iterator[Bus]:
    """A client of a host serving ``bridge/execute`` on a router of its own."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace="test", timeout=5.0)
    with (
        open_router(config),
        Bus.connect(config) as service_bus,
        ServiceHost(service_bus, "bridge", [Endpoint(EXECUTE, refuse)]),
        Bus.connect(config) as client,
    ):
        assert client.wait_alive(["bridge"], 5.0) == []
        yield client


def _refusal(client: Bus, payload: str) -> str:
    """The message of ``bridge/execute``'s ``invalid_input`` for ``payload``."""
    with pytest.raises(InvalidInputError) as refused:
        client.call(EXECUTE, payload.encode())
    return refused.value.message


def test_an_object_of_unknown_keys_is_refused_within_the_timeout(
    client: Bus,
) -> None:
    """Answered ``invalid_input`` within the bus's timeout, naming the first
    problem and counting the rest; the next such request too."""
    keys = ",".join(f'"k{i}": 1' for i in range(KEYS))
    for _ in range(2):
        message = _refusal(client, '{"trajectory": {' + keys + "}}")
        assert message == (
            "invalid ExecuteRequest: trajectory.arm: Field required; "
            f"and {KEYS + 7} more problems"
        )


def test_an_object_of_long_unknown_keys_is_refused_within_the_timeout(
    client: Bus,
) -> None:
    """Keys far longer than any field name are not compared with each
    missing field (difflib's time grows with the key's length)."""
    pattern = "joint_names_arm_times_positions_"
    long = (pattern * (LONG_KEY // len(pattern) + 1))[:LONG_KEY]
    keys = ",".join(f'"{i}{long}": 1' for i in range(LONG_KEYS))
    message = _refusal(client, '{"trajectory": {' + keys + "}}")
    assert message == (
        "invalid ExecuteRequest: trajectory.arm: Field required; "
        f"and {LONG_KEYS + 7} more problems"
    )


def test_a_list_stops_at_its_first_wrong_item(client: Bus) -> None:
    """Its first wrong item is named; the rest of the list is not looked at
    (the trajectory's seven missing fields are still counted)."""
    names = ",".join(["1"] * ITEMS)
    message = _refusal(client, '{"trajectory": {"joint_names": [' + names + "]}}")
    assert message == (
        "invalid ExecuteRequest: trajectory.arm: Field required; and 7 more problems"
    )
