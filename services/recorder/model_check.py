"""A replay of every key and a live decide service: the recorded model stays out.

The decide service swaps in every model published on ``fit/model/update``
(``services.decide.live_model``). A recording holds one whenever the fit
service published during it (at its start, after each fit), so a replay
without ``--keys`` into ``armplan up`` replaced the model the live system
decides with by the recorded one, with no word but the decide service's
log and exit 0: every later plan was decided with it, while fit served
another. As for a live bridge (``bridge_watch``), it is refused; with
``--keys`` the chosen keys go out.

Checked before the first message; a decide service that comes alive
during the replay (it asks fit for its model, then takes every later
publication) stops it, as a bridge does (``service_watch``).
"""

from __future__ import annotations

from services.recorder.replay import Replay
from services.recorder.service_watch import service_alive
from shared.bus import Bus
from shared.errors import InvalidInputError

#: The service that reads the published models.
DECIDE = "decide"
#: First key chunk of the fit service's topics (``fit/model/update``).
MODEL_CHUNK = "fit"


def model_keys(items: Replay) -> list[str]:
    """The keys of ``items`` under ``fit/`` (a live decide service reads them)."""
    return [key for key in items.counts if key.split("/")[0] == MODEL_CHUNK]


def check_no_live_decide(bus: Bus, keys: list[str]) -> None:
    """Raise: a decide service is alive and the recorded model would replace its own.

    Args:
        bus: The replay's open bus.
        keys: The ``fit/`` keys to send (empty with ``--keys``: the user
            chose them).

    Raises:
        InvalidInputError: naming the keys and how to replay them anyway.
        ServiceUnavailableError: if the router did not answer in time.
    """
    if not keys or not service_alive(bus, DECIDE, keys):
        return
    raise InvalidInputError(
        f"a decide service is alive in namespace {bus.config.namespace!r}: the "
        f"recorded {', '.join(keys)} would replace the model it decides with "
        "(every later plan's, while fit serves its own); nothing was sent. To "
        "replay it on purpose, choose the keys with --keys, e.g. --keys "
        f"{keys[0]}; to replay the rest, leave it out of --keys",
        field="keys",
    )
