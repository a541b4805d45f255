"""One process per service and namespace.

A query goes to every queryable on its key, so two planners in one
namespace both plan every request and both publish it on
``plan/trajectory``: a following robot played one ``armplan plan`` three
times. ``armplan up`` starts one of each, but its router may be linked to
another machine's (the file's ``connect`` endpoints, the cross-machine
recipe's ``robot.json5``), where another ``armplan up`` already serves the
namespace. So a service asks the router, before it declares anything,
whether its token is held already. Two started at the same moment may both
find none (the bridge has claims for that: ``bridge/claim.py``).
"""

from __future__ import annotations

from shared.bus.bus import Bus
from shared.bus.keys import alive_key
from shared.errors import ServiceRunningError


def check_alone(bus: Bus, name: str) -> None:
    """Refuse to serve ``name`` beside another process serving it.

    Raises:
        ServiceRunningError: ``<ns>/alive/<name>`` is held already.
    """
    if name in bus.alive():
        raise ServiceRunningError(
            name,
            key=alive_key(bus.config.namespace, name),
            why=f"two {name} services in one namespace would each answer every "
            f"request{_HARM.get(name, '')}",
        )


#: What two of a service would do beyond answering twice, by service.
_HARM = {
    "planner": " (and publish every plan twice for a following robot)",
    "fit": " (and each fit and publish every model)",
}
