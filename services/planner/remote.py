"""The planner's stages as the decide, ik and timing services over Zenoh.

:class:`RemoteStages` is the :class:`~services.planner.stages.Stages` of the
planner service: each stage is one query to its service, which runs the same
stage function on the same message (JSON round-trips floats exactly), so a
plan made through the services equals the in-process one. Before planning,
:meth:`RemoteStages.require` checks the liveliness of every service the
request needs, so an absent one is named at once, before any work is done.
"""

from __future__ import annotations

from typing import Any

from shared.bus import Bus, Route
from shared.bus.routes import DECIDE, IK_PATH, TIMING
from shared.errors import ServiceUnavailableError
from shared.messages import (
    DecideRequest,
    Decision,
    JointPath,
    Method,
    PathIKRequest,
    PlanRequest,
    TimingRequest,
    Trajectory,
)


def needed_routes(request: PlanRequest) -> list[Route[Any, Any]]:
    """The stage routes a plan of ``request`` calls, in the order it calls them.

    Method ``mp`` needs the decision; a task of targets needs the timing
    service (a timed wrist path keeps its own times, checked in the planner).
    """
    routes: list[Route[Any, Any]] = [DECIDE] if request.method is Method.MP else []
    routes.append(IK_PATH)
    if request.wrist_path is None:
        routes.append(TIMING)
    return routes


class RemoteStages:
    """The stages as queries to the decide, ik and timing services.

    Args:
        bus: The planner's bus.
        timeout: Longest wait for each stage's reply [s]; default the bus's.
    """

    def __init__(self, bus: Bus, timeout: float | None = None) -> None:
        self._bus = bus
        self._timeout = timeout

    def require(self, request: PlanRequest) -> None:
        """Raise at once if a service the request needs is not running.

        Raises:
            ServiceUnavailableError: naming the first absent service (and
                every absent one in its reason).
        """
        namespace = self._bus.config.namespace
        routes = needed_routes(request)
        missing = [r for r in routes if not self._bus.is_alive(r.service)]
        if missing:
            names = ", ".join(repr(r.service) for r in missing)
            raise ServiceUnavailableError(
                missing[0].service,
                key=missing[0].key(namespace),
                reason=f"the planner needs {names} and finds no liveliness token "
                f"under {namespace}/alive/ (is it started, e.g. by `armplan up`?)",
            )

    def decide(self, request: DecideRequest) -> Decision:
        return self._bus.call(DECIDE, request, timeout=self._timeout)

    def ik(self, request: PathIKRequest) -> JointPath:
        return self._bus.call(IK_PATH, request, timeout=self._timeout)

    def timing(self, request: TimingRequest) -> Trajectory:
        return self._bus.call(TIMING, request, timeout=self._timeout)
