"""The whole fault and load suite, on one freshly started system.

Order: each service killed and restarted during traffic (fit, decide, ik,
timing, planner, then the bridge), the router, the recorder, a burst of
concurrent plans, and bad inputs against every queryable (the routes of
``ROUTES`` and the bridge's ``bridge/execute``). A process that crashed is
started again before the next scenario, so one crash is counted once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from armplan.faults.bad_input import bad_input_scenario
from armplan.faults.burst import burst_scenario
from armplan.faults.kill_restart import restart_scenario
from armplan.faults.recorder_kill import recorder_scenario
from armplan.faults.requests import good_requests
from armplan.faults.system import FaultSystem
from armplan.faults.tally import Tally
from armplan.faults.traffic import Traffic
from armplan.launch.catalog import SERVICES
from shared.bus import Bus, Route
from shared.bus.queue_room import MOST_AT_ONCE, check_queue_room
from shared.bus.robot_routes import EXECUTE
from shared.bus.routes import ROUTES

#: Every process killed and restarted during traffic, in order.
KILLED: tuple[str, ...] = (*(s.name for s in SERVICES), "bridge")
#: Every queryable: the services' routes and the bridge's.
QUERYABLES: tuple[Route[Any, Any], ...] = (*ROUTES, EXECUTE)


@dataclass(frozen=True)
class SuiteOptions:
    """How big the suite is.

    Attributes:
        requests: Requests per kill scenario (a third before, during, after).
        concurrency: Client threads sending them.
        burst: Plan requests sent at once, 0 (none) to ``MOST_AT_ONCE``
            (the planner's queue limit: more would be refused ``service_busy``).
        examples: Bad inputs of each kind per queryable.
        seed: Seed of the bad inputs.
        timeout: Each request's timeout [s].
        burst_timeout: Each request's timeout in the burst [s].
        killed: Processes to kill and restart (default: every service and
            the bridge).
        router: Also kill and restart the router.
        recorder: Also kill and restart the recorder.
        queryables: Routes to send bad inputs to (default: all).
    """

    requests: int = 60
    concurrency: int = 8
    burst: int = 200
    examples: int = 4
    seed: int = 0
    timeout: float = 30.0
    burst_timeout: float = 120.0
    killed: tuple[str, ...] = KILLED
    router: bool = True
    recorder: bool = True
    queryables: tuple[Route[Any, Any], ...] = QUERYABLES

    def __post_init__(self) -> None:
        give = f"burst 0..{MOST_AT_ONCE}"
        check_queue_room(self.burst, "plans at once", give, field="burst")


def run_suite(
    out: Path,
    options: SuiteOptions,
    report: Callable[[Tally], None] = lambda tally: None,
    *,
    overwrite: bool = False,
) -> list[Tally]:
    """Start the system in ``out``, run every scenario, stop it; every tally.

    Args:
        out: The folder for the configuration, the logs and the recordings.
        options: The suite's size.
        report: Called with each scenario's tally as soon as it is done.
        overwrite: Replace an earlier run's files in ``out`` (else refused,
            see :mod:`armplan.faults.out_folder`).
    """
    fault_system = FaultSystem(out, overwrite=overwrite)  # refuses before work
    good = good_requests()
    tallies: list[Tally] = []

    def keep(tally: Tally) -> None:
        tallies.append(tally)
        report(tally)
        system.heal(bus)

    with (
        fault_system as system,
        Bus.connect(system.config) as bus,
        Traffic(bus, options.concurrency, options.timeout) as traffic,
    ):
        for name in options.killed:
            keep(restart_scenario(system, traffic, good, name, options.requests))
        if options.router:
            keep(restart_scenario(system, traffic, good, "router", options.requests))
        if options.recorder:
            keep(recorder_scenario(system, traffic, good, options.requests))
        if options.burst:
            keep(
                burst_scenario(system, bus, good, options.burst, options.burst_timeout)
            )
        for route in options.queryables:
            keep(
                bad_input_scenario(
                    system,
                    bus,
                    good,
                    route,
                    examples=options.examples,
                    seed=options.seed,
                    timeout=options.timeout,
                )
            )
    return tallies
