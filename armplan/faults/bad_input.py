"""Bad inputs against one queryable: each gets a typed error, the service lives.

For a route, hypothesis spoils its valid request in every way of
:mod:`armplan.faults.strategies` (``examples`` of each kind). Each spoiled
payload is sent raw; right after it, the service must answer a good
request, and at the end it must be the same process as at the start.
"""

from __future__ import annotations

import json
from collections import Counter
from typing import Any

from armplan.faults.outcome import Call, Outcome, send
from armplan.faults.requests import GoodRequests
from armplan.faults.strategies import SPOILERS, BadInput, draw
from armplan.faults.system import FaultSystem
from armplan.faults.tally import Tally
from shared.bus import Bus, Route


def spoiled(
    good: GoodRequests, route: Route[Any, Any], examples: int, seed: int
) -> list[BadInput]:
    """``examples`` spoiled requests of each kind for ``route``, from ``seed``."""
    template = json.loads(good.by_route[route.path].to_json())
    return [
        bad
        for spoil in SPOILERS.values()
        for bad in draw(spoil(template), examples, seed)
    ]


def bad_input_scenario(
    system: FaultSystem,
    bus: Bus,
    good: GoodRequests,
    route: Route[Any, Any],
    *,
    examples: int,
    seed: int,
    timeout: float,
) -> Tally:
    """Send every spoiled request of ``route``, each followed by a good one.

    Facts: ``bad`` (spoiled requests sent), ``typed`` (answered with a
    typed error), ``accepted`` (valid after all, answered), ``good_next``
    (good requests answered right after one), ``same_process``.
    """
    inputs = spoiled(good, route, examples, seed)
    probe = good.probe(route.service)
    pid = system.pid(route.service)
    tally = Tally(f"bad input: {route.path}", faults=len(inputs))
    outcomes: Counter[Outcome] = Counter()
    good_next = 0
    for bad in inputs:
        got = send(bus, Call(route, bad.payload), timeout)
        then = send(bus, probe, timeout)
        tally.add([got, then])
        outcomes[got.outcome] += 1
        good_next += then.outcome is Outcome.SUCCEEDED
    same = system.pid(route.service) == pid and system.running()[route.service]
    tally.facts = {
        "bad": len(inputs),
        "typed": outcomes[Outcome.TYPED],
        "accepted": outcomes[Outcome.SUCCEEDED],
        "good_next": good_next,
        "same_process": same,
        "note": f"{outcomes[Outcome.TYPED]}/{len(inputs)} typed errors, "
        f"{outcomes[Outcome.SUCCEEDED]} valid after all; good request next "
        f"{good_next}/{len(inputs)}; "
        + ("same process" if same else "process CHANGED"),
    }
    tally.crashes = system.crashes()
    return tally
