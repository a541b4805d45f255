"""Where a plan's time goes through the services: each stage, here and there.

The planner service calls decide, ik and timing one after another. This
benchmark sends those three requests (the ones the planner sends for the
one-second reach) straight to their services, in rounds in the planner's
order, and then runs the same three stage functions on the same requests in
this process, in rounds too. Both sides thus run the stages as a plan does,
one after the other (interleaving each stage here with its own trip through
the service made both slower: each evicts the other's working set from the
CPU's caches). Per stage:

- ``here``: the stage in this process [s] (for ik: tracking the path again
  with the decided primitives, as the ik service does, not the decision's
  joint path reused as the in-process planner does);
- ``service``: the same request through the router to the service and back
  [s]: the stage's work in the service's process, plus the request's and the
  reply's JSON on both sides and the trips through the router;
- ``overhead``: service minus here, at the median [s];
- ``handle`` and ``inside``: what the service says it spent (its replies'
  ``ServiceTiming``): the stage function alone, and with reading the request
  and writing the reply; ``service`` minus ``inside`` is the trips through
  Zenoh and the router and this side's JSON [s].

The sum of the three ``service`` medians beside a whole plan through the
services (``service_latency``) shows what the planner itself and the
client's hop add.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any, NamedTuple

import numpy as np

from armplan.bench.timer import Timing, time_rounds
from services.planner import stages, timing_stage
from services.planner.keeping_stages import KeepingStages
from services.planner.pipeline import plan
from shared.bus import Bus, Route
from shared.bus.routes import DECIDE, IK_PATH, TIMING
from shared.errors import RemoteError
from shared.messages import Message, PlanRequest, ServiceTiming

#: The stages, in the planner's order.
STAGES = ("decide", "ik", "timing")
_ROUTES: dict[str, Route[Any, Any]] = {
    "decide": DECIDE,
    "ik": IK_PATH,
    "timing": TIMING,
}


class StageHop(NamedTuple):
    """One stage's times here and through its service [s].

    Attributes:
        here: The stage function in this process, per call [s].
        service: The same request through its service, per call [s].
        handle: The stage function in the service's process, as the service
            timed it, per call [s].
        inside: ``handle`` plus the service's reading of the request and
            writing of the reply, per call [s].
    """

    here: Timing
    service: Timing
    handle: Timing
    inside: Timing

    @property
    def overhead(self) -> float:
        """Median through the service minus median here [s]."""
        return self.service.percentile(50) - self.here.percentile(50)

    @property
    def trips(self) -> float:
        """Median through the service minus median inside it [s].

        Zenoh's trips there and back, the router, and this side's JSON.
        """
        return self.service.percentile(50) - self.inside.percentile(50)


def stage_requests(request: PlanRequest) -> dict[str, Message]:
    """The decide, ik and timing requests the planner sends for ``request``.

    Raises:
        ValueError: if ``request`` does not go through all three stages
            (a timed wrist path, or a baseline method).
    """
    keeping = KeepingStages()
    plan(request, keeping)
    missing = [name for name in STAGES if _ROUTES[name].path not in keeping.asked]
    if missing:
        raise ValueError(f"the plan does not call the stage(s) {missing}")
    return {name: keeping.asked[_ROUTES[name].path] for name in STAGES}


def _here(name: str, request: Any) -> Callable[[], object]:
    """The stage as its service computes it, in this process."""
    if name == "decide":
        return partial(stages.decide, stages.default_decider(), request)
    if name == "ik":
        return partial(stages.path_ik, request)
    return partial(timing_stage.timing, request)


def steps(rounds: int) -> int:
    """How many timed calls :func:`time_hops` makes (for a progress bar)."""
    return 2 * len(STAGES) * rounds


def time_hops(
    bus: Bus,
    request: PlanRequest,
    rounds: int,
    after: Callable[[], object] | None = None,
) -> dict[str, StageHop]:
    """Time each stage of ``request`` here and through its running service.

    Args:
        bus: A bus connected to running decide, ik and timing services.
        request: The plan whose stage requests are sent (method ``mp``,
            targets).
        rounds: Calls per stage and place: rounds of the three stages
            through the services, then rounds of the three here.
        after: Called after each timed call, untimed (progress).
    """
    requests = stage_requests(request)
    here = {name: _here(name, requests[name]) for name in STAGES}
    told: dict[str, list[ServiceTiming]] = {name: [] for name in STAGES}
    there = {name: _there(bus, name, requests[name], told[name]) for name in STAGES}
    for call in [*here.values(), *there.values()]:  # code loaded, routes known
        call()
    for kept in told.values():
        kept.clear()
    timed_there = time_rounds(there, rounds, after, warm=False)  # warmed above
    timed_here = time_rounds(here, rounds, after, warm=False)
    return {
        name: StageHop(
            timed_here[name],
            timed_there[name],
            Timing(np.array([t.handle for t in told[name]])),
            Timing(np.array([t.total for t in told[name]])),
        )
        for name in STAGES
    }


def _there(
    bus: Bus, name: str, request: Message, told: list[ServiceTiming]
) -> Callable[[], object]:
    """The stage through its service; keeps what the service says it spent.

    Raises:
        RemoteError: if the service's reply does not say (not armplan's).
    """

    def ask() -> object:
        reply, timing = bus.call_timed(_ROUTES[name], request, timeout=60.0)
        if timing is None:
            raise RemoteError(
                f"the {name} service's reply carries no ServiceTiming",
                service=name,
            )
        told.append(timing)
        return reply

    return ask
