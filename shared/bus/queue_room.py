"""How many plans may be sent at once: no more than the planner lets wait.

A service lets ``DEFAULT_QUEUE_LIMIT`` requests wait for a worker
(``BusConfig.queue_limit``) and answers any more ``service_busy``. A run
that sends more plans at the same moment (``armplan bench --clients``,
``armplan faults --burst``) would see the extra ones refused by design,
not by fault, so it is refused before any work.
"""

from __future__ import annotations

from shared.bus.config import DEFAULT_QUEUE_LIMIT
from shared.errors import InvalidInputError

#: Most plans sent at once: the planner's queue limit (requests waiting).
MOST_AT_ONCE = DEFAULT_QUEUE_LIMIT


def check_queue_room(count: int, what: str, give: str, *, field: str) -> int:
    """``count`` if the planner can let that many plans wait at once.

    Args:
        count: Plans sent at the same moment, e.g. ``300``.
        what: Who sends them, in words, e.g. ``"clients"``.
        give: What to give instead, e.g. ``"each count 1..256"``.
        field: The option or attribute named in the error.

    Raises:
        InvalidInputError: ``count`` is above ``MOST_AT_ONCE``, naming both.
    """
    if count > MOST_AT_ONCE:
        raise InvalidInputError(
            f"{count} {what} are more than the planner's queue limit "
            f"({MOST_AT_ONCE} requests waiting): the extra plans would be "
            f"refused service_busy; give {give}",
            field=field,
            limit=MOST_AT_ONCE,
        )
    return count
