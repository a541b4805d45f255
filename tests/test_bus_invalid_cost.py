"""A request with many wrong objects is refused as fast as one with a few.

Finding the misspelt key (``shared.messages.base``) scanned every error
for each missing field: a ``bridge/execute`` request whose trajectory held
4000 unknown objects (32 kB) kept a worker 15 s, four times as many 16
times as long, so a few requests far under ``max_payload`` held every
worker for hours. A real router, a service host serving the bridge's
``bridge/execute`` route (its parsing is the host's, before any handler),
a client calling it with raw bytes.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from shared.bus import Bus, BusConfig, Endpoint, ServiceHost, open_router
from shared.bus.robot_routes import EXECUTE
from shared.errors import InvalidInputError
from shared.messages import ExecuteReply, ExecuteRequest

ROUTER = "tcp/127.0.0.1:54314"
#: Unknown objects in the request's ``palm_reached`` (each a missing field
#: beside an unknown key): about 64 kB of JSON, a minute's work before.
OBJECTS = 8000


def refuse(request: ExecuteRequest) -> ExecuteReply:
    """The handler: never reached by an invalid request."""
    raise InvalidInputError("not played in this test", field="trajectory")


@pytest.fixture
def client() -> Iterator[Bus]:
    """A client of a host serving ``bridge/execute`` on a router of its own."""
    config = BusConfig(endpoints=(ROUTER,), namespace="test", timeout=5.0)
    with (
        open_router(config),
        Bus.connect(config) as service_bus,
        ServiceHost(service_bus, "bridge", [Endpoint(EXECUTE, refuse)]),
        Bus.connect(config) as client,
    ):
        assert client.wait_alive(["bridge"], 5.0) == []
        yield client


def test_thousands_of_unknown_objects_are_refused_within_the_timeout(
    client: Bus,
) -> None:
    """Answered ``invalid_input`` naming the first problem and counting the
    rest, within the bus's timeout, and the next request is answered too."""
    objects = ",".join(['{"q": 1}'] * OBJECTS)
    payload = '{"trajectory": {"palm_reached": [' + objects + "]}}"
    for _ in range(2):
        with pytest.raises(InvalidInputError) as refused:
            client.call(EXECUTE, payload.encode())
        assert refused.value.message.startswith(
            "invalid ExecuteRequest: trajectory.arm: Field required; and "
        )
        assert f"{4 * OBJECTS + 7} more problems" in refused.value.message
