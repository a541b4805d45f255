"""The planner's stages as the decide, ik and timing services over Zenoh.

:class:`RemoteStages` is the :class:`~services.planner.stages.Stages` of the
planner service: each stage is one query to its service, which runs the same
stage function on the same message (JSON round-trips floats exactly), so a
plan made through the services equals the in-process one. Before planning,
:meth:`RemoteStages.require` checks the liveliness of every service the
request needs, so an absent one is named at once, before any work is done.

Each stage waits what the planner's caller has left, less
:func:`stage_margin`: a stage service that stalls (a paused process) is
then named to the caller by the planner's answer ("service 'timing' did
not answer ..."), which arrives before the caller stops waiting. With the
bus's whole timeout for each stage, the caller's own timeout came first,
and it was told that the planner did not answer. A caller who waits longer
than the bus's timeout (``armplan plan --remote --timeout 30``) gives the
stages that long too, up to :data:`STAGE_LIMIT` each: capped at the bus's
5 s, a stage queued behind other clients' plans failed the call at 5 s
though its caller still waited.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeVar

from shared.bus import Bus, Route
from shared.bus.caller import Check
from shared.bus.deadline import REPLY_MARGIN, current_due
from shared.bus.elsewhere import HINT_TIMEOUT, elsewhere_hint
from shared.bus.routes import DECIDE, IK_PATH, TIMING
from shared.errors import ServiceUnavailableError
from shared.messages import (
    DecideRequest,
    Decision,
    JointPath,
    Message,
    Method,
    PathIKRequest,
    PlanRequest,
    TimingRequest,
    Trajectory,
)

Rep = TypeVar("Rep", bound=Message)


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


#: Most time kept back from a stage's wait for the planner's answer to
#: travel to its caller [s].
STAGE_MARGIN = 0.25
#: Longest wait for one stage however long the caller waits [s] (unless the
#: bus's timeout is longer): a stage service that hangs while connected
#: holds a planner worker that long at most, not for a caller's day-long
#: timeout (a caller that stopped waiting may still ask again; one whose
#: session ended is seen gone: :func:`checking`).
STAGE_LIMIT = 60.0


def stage_margin(budget: float) -> float:
    """Time kept back for the planner's answer to travel [s].

    A tenth of the caller's ``budget`` [s], between
    :data:`~shared.bus.deadline.REPLY_MARGIN` and :data:`STAGE_MARGIN`.
    """
    return max(REPLY_MARGIN, min(STAGE_MARGIN, 0.1 * budget))


#: What the stages' calls check while they wait (:func:`checking`).
_check: ContextVar[Check | None] = ContextVar("stage_check", default=None)


@contextmanager
def checking(check: Check) -> Iterator[None]:
    """Inside the block, each stage's wait calls ``check`` about twice a second.

    What it raises ends the wait (the planner: every caller of the plan has
    gone, so the stage is waited for no longer: a stage that hangs while
    connected held a planner worker up to :data:`STAGE_LIMIT` for a caller
    interrupted long before).
    """
    token = _check.set(check)
    try:
        yield
    finally:
        _check.reset(token)


class RemoteStages:
    """The stages as queries to the decide, ik and timing services.

    Args:
        bus: The planner's bus.
        timeout: Longest wait for each stage's reply [s] while no caller
            with time left is served; default the bus's. While the caller
            of the query being served (``current_due``) has time left, each
            stage waits that, less :func:`stage_margin`, longer or shorter
            than ``timeout`` (but at most :data:`STAGE_LIMIT` or
            ``timeout``, the longer); once it has gone, the plan goes on for a
            repeat of the request that waits for it (``answer_once``), and
            each stage waits ``timeout`` again.
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
            elsewhere = self._bus.alive_elsewhere(
                (r.service for r in missing), self._hint_time()
            )
            raise ServiceUnavailableError(
                missing[0].service,
                key=missing[0].key(namespace),
                reason=f"the planner needs {names} and finds no liveliness token "
                f"under {namespace}/alive/ (is it started, e.g. by `armplan up`?)"
                f"{elsewhere_hint(elsewhere)}",
                elsewhere=elsewhere,
            )

    def _hint_time(self) -> float:
        """How long the "alive elsewhere" hint may take [s]: within the caller's time.

        At most ``HINT_TIMEOUT``, and no longer than the caller of the query
        being served has left, less :func:`stage_margin` (0: no hint).
        """
        due = current_due()
        if due is None:
            return HINT_TIMEOUT
        left = due.at - time.monotonic() - stage_margin(due.budget)
        return min(HINT_TIMEOUT, left)

    def decide(self, request: DecideRequest) -> Decision:
        return self._ask(DECIDE, request)

    def ik(self, request: PathIKRequest) -> JointPath:
        return self._ask(IK_PATH, request)

    def timing(self, request: TimingRequest) -> Trajectory:
        return self._ask(TIMING, request)

    def _ask(self, route: Route[Any, Rep], request: Message) -> Rep:
        """A stage's answer, waited for :meth:`_wait` at most (see :func:`checking`)."""
        return self._bus.call(route, request, timeout=self._wait(), check=_check.get())

    def _wait(self) -> float:
        """The next stage's longest wait [s]."""
        wait = self._bus.config.timeout if self._timeout is None else self._timeout
        due = current_due()
        if due is None:  # not serving a query, or its caller gave no budget
            return wait
        left = due.at - time.monotonic() - stage_margin(due.budget)
        if left <= 0.0:  # its caller has gone; a repeat may wait for the plan
            return wait
        return min(left, max(wait, STAGE_LIMIT))  # longer than the bus's: asked
