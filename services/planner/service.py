"""The planner service: the public entry point ``armplan/plan``.

Keys (namespace ``armplan`` by default):
    ``armplan/plan``             PlanRequest -> Trajectory (``routes.PLAN``)
    ``armplan/plan/request``     publication: each valid request, before planning
    ``armplan/plan/joint_path``  publication: each reach's JointPath
    ``armplan/plan/trajectory``  publication: each finished Trajectory
    ``armplan/plan/decision``    publication: each reach's Decision (method mp),
                                 on the trajectory's clock, after it

It runs the in-process planner (``services.planner.pipeline.plan``) with
its stages as the decide, ik and timing services (``remote.RemoteStages``),
so a plan made here equals one made in-process. A request repeating a
recent ``request_id`` gets the first one's answer, planned and published
once (``answer_once.AnswerOnce``; once that answer is no longer kept, the
repeat is planned again and answered, still not published). A plan
finished after its callers (the first and any repeat, ``waiting.Waiting``)
stopped waiting (``shared.bus.deadline``) is not published: a robot that
follows the trajectories would otherwise move for no one. A service it
needs that is not running gives a ``service_unavailable`` error naming it at once (its
liveliness token is checked before any work); once it is back, the next
plan works. The parts are published so that a recorder subscribed to the
topics (``shared.bus.topics``) keeps the whole session. Run it with
``python -m services.planner`` (``armplan up`` does).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from typing import Any

from services.planner.answer_once import AnswerOnce
from services.planner.pipeline import PlanResult, plan
from services.planner.remote import RemoteStages, checking
from services.planner.waiting import Waiting
from shared.bus import Bus, Endpoint
from shared.bus.deadline import Due, current_due
from shared.bus.routes import PLAN, TRAJECTORY_TOPIC
from shared.bus.topics import DECISION_TOPIC, JOINT_PATH_TOPIC, PLAN_REQUEST_TOPIC
from shared.errors import RequestTimeoutError
from shared.messages import PlanRequest, Trajectory
from shared.messages.target import MAX_TRAJECTORY_SAMPLES

NAME = "planner"
log = logging.getLogger("armplan.planner")
#: Most trajectory samples the answers kept for repeats hold together: two
#: trajectories of the most samples a message carries
#: (``MAX_TRAJECTORY_SAMPLES``), about 100 MB as Python objects (a kept
#: 40 000-sample trajectory measured 34 MB), against thousands of short reaches.
KEPT_SAMPLES = 2 * MAX_TRAJECTORY_SAMPLES
Planner = Callable[[PlanRequest], Trajectory]


def remote_planner(bus: Bus) -> Planner:
    """Plan through the stage services, publishing the request and every part."""
    stages = RemoteStages(bus)
    once: AnswerOnce[PlanRequest, Trajectory] = AnswerOnce(
        PlanRequest.to_json, weight=samples, budget=KEPT_SAMPLES
    )
    waiting = Waiting()
    bus.caller_gone(None)  # watch callers' sessions end from the start

    def plan_and_publish(request: PlanRequest) -> Trajectory:
        bus.publish(PLAN_REQUEST_TOPIC, request)
        stages.require(request)
        due = current_due()

        def refuse_if_gone(when: str) -> None:
            """Raise if every caller has gone: a robot would move for no one."""
            if waiting.all_gone(request.request_id, due, bus.caller_gone):
                raise _gone_error(bus, due, when)

        def refuse_if_ended() -> None:
            """Raise if every caller's session has ended: no one to plan for."""
            if waiting.all_ended(request.request_id, due, bus.caller_gone):
                log.warning(
                    "plan %s: every caller's session ended while a stage was "
                    "asked; the planner stopped waiting for it",
                    request.request_id or "(no request_id)",
                )
                raise _gone_error(bus, due, "while its stages were asked")

        with checking(refuse_if_ended):
            result = plan(request, stages)
        refuse_if_gone("before the plan was ready")
        publish_parts(
            bus,
            result,
            lambda: refuse_if_gone("while its joint paths were published"),
        )
        return result.trajectory

    def plan_again(request: PlanRequest) -> Trajectory:
        """A repeat's answer once the first one's is no longer kept.

        The same plan, not published again (the robot follows it once).
        """
        stages.require(request)
        return plan(request, stages).trajectory

    def plan_remotely(request: PlanRequest) -> Trajectory:
        with waiting.caller(request.request_id, current_due()):
            return once.answer(
                request.request_id,
                request,
                lambda: plan_and_publish(request),
                again=lambda: plan_again(request),
            )

    return plan_remotely


def _gone_error(bus: Bus, due: Due | None, when: str) -> RequestTimeoutError:
    """The error of a plan not published: its callers had gone ``when``.

    ``when``: e.g. "before the plan was ready".
    """
    budget = 0.0 if due is None else due.budget
    why = (
        "the caller's session ended (interrupted or killed)"
        if due is not None and not due.too_late and bus.caller_gone(due.session)
        else f"the caller stopped waiting after {budget:.3f} s,"
    )
    return RequestTimeoutError(
        NAME,
        key=PLAN.key(bus.config.namespace),
        timeout=budget,
        message=f"{why} {when}: it was not published (a robot would have moved "
        "for no one)",
    )


def samples(trajectory: Trajectory) -> int:
    """A kept answer's weight: its sample count."""
    return len(trajectory.times)


def publish_parts(
    bus: Bus, result: PlanResult, before_trajectory: Callable[[], None] = lambda: None
) -> None:
    """Publish a plan's joint paths, trajectory and decisions, in that order.

    ``before_trajectory`` runs after the joint paths, and may raise to
    publish no trajectory: a put may wait up to 5 s for a subscriber that
    stopped reading (``Bus.publish``'s BLOCK), long enough for the caller
    to stop waiting meanwhile.

    The decisions come right after the trajectory: a recording places each
    decision point at its decision's arrival plus when the trajectory
    passes it (``Decision.trajectory_times``), so that arrival stands for
    the trajectory's (5 ms later in ``tests/test_recorder_plan_decisions``).
    Before the trajectory they arrived its JSON's encoding earlier (73 ms
    for the demo's task).
    """
    for joint_path in result.joint_paths:
        bus.publish(JOINT_PATH_TOPIC, joint_path)
    before_trajectory()
    bus.publish(TRAJECTORY_TOPIC, result.trajectory)
    for decision in result.decisions:
        bus.publish(DECISION_TOPIC, decision)


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The planner's endpoint; it calls decide, ik and timing."""
    return [Endpoint(PLAN, remote_planner(bus))]
