"""Kill a process during traffic, send while it is down, restart it, send again.

The calls go out in three thirds: the first third, with the process killed
(SIGKILL) once half of it has been answered, so calls are in flight at the
kill; the second third at once, while it is down; then the process is
started again, and once every process holds its liveliness token again the
last third goes out. For a service, the calls alternate plans with a
request the killed service answers itself, so some calls must fail naming
it; for the router, every call is a plan.
"""

from __future__ import annotations

import time
from typing import NamedTuple

from armplan.faults.outcome import Call, Outcome, Result
from armplan.faults.requests import GoodRequests
from armplan.faults.system import FaultSystem
from armplan.faults.tally import Tally
from armplan.faults.traffic import Traffic, cycle
from shared.bus.robot_routes import EXECUTE
from shared.bus.routes import PLAN

#: Longest wait for every process to be alive again after a restart [s].
ALIVE_TIMEOUT = 90.0


class Phases(NamedTuple):
    """The results around one kill.

    Attributes:
        before: Calls sent before the kill (some in flight at it).
        settled: Those of ``before`` answered at least the ``settle`` time
            of :func:`kill_and_restart` before the kill.
        down: Calls sent while the process was down.
        after: Calls sent once every process was alive again.
        down_s: From the kill to every process alive again [s].
        missing: Processes still not alive after ``ALIVE_TIMEOUT``.
    """

    before: list[Result]
    settled: list[Result]
    down: list[Result]
    after: list[Result]
    down_s: float
    missing: list[str]

    def all(self) -> list[Result]:
        """Every result, in the order sent."""
        return [*self.before, *self.down, *self.after]


def kill_and_restart(
    system: FaultSystem,
    traffic: Traffic,
    calls: list[Call],
    name: str,
    *,
    settle: float = 0.0,
) -> Phases:
    """Send ``calls`` in thirds around killing and restarting process ``name``.

    Once half the first third is answered, wait ``settle`` [s], then kill
    (the recorder: so that what was answered by then has been flushed).
    """
    third = len(calls) // 3
    before = traffic.send(calls[:third])
    traffic.wait_done(before, len(before) // 2)
    settled = [f.result() for f in before if f.done()]
    time.sleep(settle)
    killed = time.monotonic()
    system.kill(name)
    down = traffic.send(calls[third : 2 * third])
    before_results, down_results = traffic.results(before), traffic.results(down)
    system.restart(name)
    missing = system.wait_alive(traffic.bus, ALIVE_TIMEOUT)
    back = time.monotonic() - killed
    after = traffic.run(calls[2 * third :])
    return Phases(before_results, settled, down_results, after, back, missing)


def names(result: Result, name: str) -> bool:
    """Whether ``result`` is a ``service_unavailable`` error naming ``name``.

    With the router down every service is unavailable, so for the router
    any ``service_unavailable`` counts: the message says the router was
    lost only once this client has noticed; a call sent just before that
    is told the service's token or queryable is gone (:func:`_said`).
    """
    if result.kind != "service_unavailable":
        return False
    return name == "router" or result.service == name


def _said(results: list[Result], name: str, needing: int) -> str:
    """How the calls sent while ``name`` was down failed, in words."""
    named = sum(names(r, name) for r in results)
    if name != "router":
        return (
            f"{named} of the {needing} calls sent while down that need {name} "
            "failed naming it"
        )
    said = sum("router" in r.message for r in results)
    return (
        f"{named} of the {needing} calls sent while down were service_unavailable "
        f"({said} saying the router was lost)"
    )


def needs(result: Result, name: str, probe_path: str) -> bool:
    """Whether the call behind ``result`` needs process ``name`` to be up.

    Every call needs the router; a plan needs the planner and its stages;
    a probe needs the service it probes.
    """
    stages = ("decide", "ik", "timing", "planner")
    plan = result.route == PLAN.path and name in stages
    return name == "router" or plan or result.route == probe_path


def _recovered(after: list[Result]) -> bool:
    """Whether every call after the restart was answered as a healthy system would.

    That is a result, or for an execute overlapping another the typed
    ``robot_busy`` (the robot plays one trajectory at a time), with at least
    one result on every route asked.
    """
    answered = {r.route for r in after if r.outcome is Outcome.SUCCEEDED}
    return all(
        r.outcome is Outcome.SUCCEEDED
        or (r.route == EXECUTE.path and r.kind == "robot_busy")
        for r in after
    ) and answered == {r.route for r in after}


def traffic_calls(good: GoodRequests, name: str, count: int) -> list[Call]:
    """``count`` calls: plans, alternating with requests ``name`` answers."""
    plans = good.plan_calls()
    if name in ("router", "planner", "recorder"):
        return cycle(plans, count)
    probe = good.probe(name)
    return cycle([c for plan in plans for c in (plan, probe)], count)


def restart_scenario(
    system: FaultSystem, traffic: Traffic, good: GoodRequests, name: str, count: int
) -> Tally:
    """Kill and restart process ``name`` (a service, the bridge or the router).

    Facts: ``named`` (calls sent while it was down that failed naming it),
    ``down_needing`` (calls sent while it was down that need it),
    ``recovered`` (every call after the restart succeeded, or was an
    execute refused ``robot_busy`` while another played),
    ``down_s`` and ``missing``.
    """
    tally = Tally(f"kill, restart {name}", faults=1)
    phases = kill_and_restart(system, traffic, traffic_calls(good, name, count), name)
    tally.add(phases.all())
    named = sum(names(r, name) for r in phases.down)
    probe = "" if name in ("router", "planner") else good.probe(name).route.path
    needing = sum(needs(r, name, probe) for r in phases.down)
    recovered = _recovered(phases.after)
    busy = sum(r.kind == "robot_busy" for r in phases.after)
    said = _said(phases.down, name, needing)
    tally.facts = {
        "named": named,
        "down_needing": needing,
        "recovered": recovered and not phases.missing,
        "down_s": round(phases.down_s, 2),
        "missing": phases.missing,
        "note": f"{said}; all alive after {phases.down_s:.1f} s; "
        + ("every later call succeeded" if recovered else "NOT recovered")
        + (
            f" ({busy} executes refused robot_busy: one robot plays one trajectory "
            "at a time)"
            if busy
            else ""
        ),
    }
    tally.crashes = system.crashes()
    return tally
