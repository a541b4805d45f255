"""A replay of every key and a live bridge: which keys it takes, the check before.

A replay without ``--keys`` is refused when a bridge is alive in its
namespace (``armplan replay``): the recorded trajectories would go to it
and, with ``--follow``, be played on the arm again. A bridge that comes
alive during the replay stops it (``services.recorder.service_watch``).
"""

from __future__ import annotations

from services.recorder.replay import Replay
from services.recorder.service_watch import service_alive
from shared.bus import Bus
from shared.errors import InvalidInputError

#: The service whose liveliness token is checked and watched.
BRIDGE = "bridge"
#: First key chunks a live bridge acts on (``plan/trajectory``: a bridge
#: with ``--follow`` plays it) or whose messages would mix with the live
#: ones (the planner's ``plan/*``, the bridge's own ``bridge/*``).
LIVE_CHUNKS = ("plan", "bridge")


def live_keys(items: Replay) -> list[str]:
    """The keys of ``items`` a live bridge acts on or mixes with (``LIVE_CHUNKS``)."""
    return [key for key in items.counts if key.split("/")[0] in LIVE_CHUNKS]


def check_no_live_bridge(bus: Bus, live: list[str]) -> None:
    """Raise: a bridge is alive and the whole recording would go to it.

    A replay of every recorded key into a live system played the recorded
    trajectories again on the robot (a bridge with ``--follow``) and mixed
    old ``bridge/*`` messages into the live recording, with no word and
    exit 0. Replaying into a live robot is done on purpose, with ``--keys``.

    Args:
        bus: The replay's open bus.
        live: The keys to send that a bridge acts on or mixes with (empty
            with ``--keys``: the user chose them).

    The router's answer is waited for up to ``bus.config.timeout``; a
    query it did not answer in time ended with Zenoh's "Timeout" reply
    alone, which read as "no bridge": over a stalled link the whole
    recording went to a bridge alive before the replay (the watch, declared
    without history, sees only tokens newer than itself). No answer now
    refuses the replay too.

    Raises:
        InvalidInputError: naming the keys and how to replay them anyway.
        ServiceUnavailableError: if the router did not answer in time.
    """
    if not live or not service_alive(bus, BRIDGE, live):
        return
    raise InvalidInputError(
        f"a bridge is alive in namespace {bus.config.namespace!r}: the recorded "
        f"{', '.join(live)} would go to it (a bridge with --follow moves the "
        "robot again) and mix with the live messages; nothing was sent. To "
        "replay into a live robot on purpose, choose the keys with --keys, "
        "e.g. --keys plan/trajectory --wait-for bridge",
        field="keys",
    )
