"""One bridge per namespace, also when two start at the same moment.

:func:`check_alone` asks whether a bridge's service token is held
before this bridge declares anything; two bridges started together (two
``armplan up`` at once) both find none, and both would play every request
on the robot. So each bridge also holds a claim token,
``<ns>/bridge/claim/<start [ns since the epoch]>-<session id>``, from
before its queryables until it exits. It waits :data:`SETTLE` for a claim
made at the same moment to reach it, then gives way to any earlier claim.
A bridge that runs keeps its claim, so one that starts later gives way to
it even before its service token is seen.

The start times are the hosts' clocks: two bridges on machines whose
clocks differ by more than the gap between their starts could each take
the other's claim for the later one. One machine per robot, as deployed,
compares one clock.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

from shared.bus import Bus
from shared.bus.keys import alive_key
from shared.bus.liveness import QUERY_TIMEOUT
from shared.bus.robot_routes import BRIDGE
from shared.errors import ServiceRunningError

#: How long a new claim waits for one made at the same moment [s]: a token
#: crosses the router in milliseconds on one host.
SETTLE = 0.3

#: The claims' key below the namespace.
CLAIMS = "bridge/claim"


def check_alone(bus: Bus) -> None:
    """Refuse to start beside another bridge in the namespace.

    Asked of the router (a liveliness query) before this bridge declares
    anything.

    Raises:
        ServiceRunningError: ``<ns>/alive/bridge`` is held already.
    """
    if BRIDGE in bus.alive():
        raise ServiceRunningError(
            BRIDGE,
            key=alive_key(bus.config.namespace, BRIDGE),
            why="two bridges would both play every request on the robot",
        )


def claim_key(namespace: str, started_ns: int, session_id: str) -> str:
    """The claim token's key; claims sort by start time, then session id."""
    return f"{namespace}/{CLAIMS}/{started_ns:020d}-{session_id}"


def claims(bus: Bus) -> list[str]:
    """Every bridge claim held in ``bus``'s namespace now, earliest first."""
    pattern = f"{bus.config.namespace}/{CLAIMS}/*"
    replies = bus.session.liveliness().get(pattern, timeout=QUERY_TIMEOUT)
    return sorted(str(r.ok.key_expr) for r in replies if r.ok is not None)


@contextmanager
def sole_bridge(bus: Bus, stop: threading.Event) -> Iterator[None]:
    """Hold this bridge's claim inside; refuse beside another bridge.

    First :func:`check_alone`; then the claim, and a refusal if an earlier
    claim is held.

    Args:
        bus: The bridge's open bus.
        stop: Set when the bridge is told to stop (ends the wait early).

    Raises:
        ServiceRunningError: another bridge serves the namespace, or
            claimed it first.
    """
    check_alone(bus)
    namespace = bus.config.namespace
    mine = claim_key(namespace, time.time_ns(), str(bus.session.info.zid()))
    token = bus.session.liveliness().declare_token(mine)
    try:
        stop.wait(SETTLE)
        earlier = [key for key in claims(bus) if key < mine]
        if earlier:
            raise ServiceRunningError(
                BRIDGE,
                key=earlier[0],
                why="another bridge started at the same moment, and first; two "
                "bridges would both play every request on the robot",
            )
        yield
    finally:
        token.undeclare()  # type: ignore[no-untyped-call]
