"""Many plan requests at once: every one planned, none lost.

``count`` client threads on one bus each send one plan request at the same
moment (reaches to NAO's 16 grid targets, in turn). No fault is injected:
the services queue what they cannot start at once and must plan every
request. ``count`` is at most the planner's queue limit
(:data:`~shared.bus.queue_room.MOST_AT_ONCE`); a full queue would answer
``service_busy``, a typed error, and any plan that fails is a broken
promise (:func:`~armplan.faults.tally.unmet`).
"""

from __future__ import annotations

import time

from armplan.faults.outcome import Outcome
from armplan.faults.requests import GoodRequests
from armplan.faults.system import FaultSystem
from armplan.faults.tally import Tally
from armplan.faults.traffic import Traffic, cycle
from shared.bus import Bus


def burst_scenario(
    system: FaultSystem, bus: Bus, good: GoodRequests, count: int, timeout: float
) -> Tally:
    """Send ``count`` plan requests at once, each with ``timeout`` [s].

    Facts: ``burst`` (plans sent), ``planned`` (those that succeeded: all
    of them, or the promise is broken), ``wall_s`` (until the last answer)
    and ``slowest_s``.
    """
    tally = Tally(f"{count} concurrent plans")
    start = time.monotonic()
    with Traffic(bus, count, timeout) as traffic:
        results = tally.add(traffic.run(cycle(good.plan_calls(), count)))
    wall = time.monotonic() - start
    slowest = max((r.seconds for r in results), default=0.0)
    done = sum(r.outcome is Outcome.SUCCEEDED for r in results)
    tally.facts = {
        "burst": count,
        "planned": done,
        "wall_s": round(wall, 2),
        "slowest_s": round(slowest, 2),
        "note": f"{done}/{count} planned in {wall:.1f} s; "
        f"slowest answer {slowest:.1f} s (timeout {timeout:.0f} s)",
    }
    tally.crashes = system.crashes()
    return tally
