"""An overloaded planner: told busy means not planned, answered means once.

The planner and its stage services as real processes, with one worker and
one queue slot each, and callers that ask again after 0.2 s as
``armplan plan --remote`` does (``repeat=True``). A second query refused
``service_busy`` while the first was still queued or running used to be
its caller's answer: 11 of 12 callers of 64-target plans were told busy,
and 10 of those plans were planned and published anyway (a following
robot would play motions whose callers were told they failed, and play
them twice for a caller that then asked again).
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor

import pytest

from armplan.launch import Launcher, free_endpoint
from shared.bus import Bus, load_config
from shared.bus.routes import PLAN, TRAJECTORY_TOPIC
from shared.bus.topics import PLAN_REQUEST_TOPIC
from shared.demos.nao_grid import nao_grid
from shared.errors import ServiceBusyError
from shared.messages import PlanRequest, Trajectory
from shared.messages.request_id import with_request_id

NAMESPACE = "test-busy"
CONFIG = """{{
  mode: "router",
  listen: {{ endpoints: ["{endpoint}"] }},
  scouting: {{ multicast: {{ enabled: false }} }},
  metadata: {{ armplan: {{ namespace: "{namespace}", timeout: 60.0,
                          resend_after: 0.2, workers: 1, queue_limit: 1 }} }},
}}"""
#: Callers asking at once: one plan runs, one waits, the rest are refused.
CALLERS = 8


@pytest.fixture(scope="module")
def stack(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Launcher]:
    """The router and every service: one worker, one queue slot each."""
    folder = tmp_path_factory.mktemp("busy")
    path = folder / "zenoh.json5"
    path.write_text(CONFIG.format(endpoint=free_endpoint(), namespace=NAMESPACE))
    with (
        (folder / "children.log").open("w") as log,
        Launcher(load_config(path), log=log) as launcher,
    ):
        yield launcher


def tasks() -> list[PlanRequest]:
    """``CALLERS`` different 16-target tasks, each with its own request id."""
    goals = [tuple(g.wrist) for g in nao_grid("right")]
    return [
        with_request_id(
            PlanRequest.model_validate(
                {"targets": [{"position": p} for p in goals[k:] + goals[:k]]}
            )
        )
        for k in range(CALLERS)
    ]


def ask(bus: Bus, task: PlanRequest) -> Trajectory | ServiceBusyError:
    """The plan, or the busy refusal (any other error fails the test)."""
    try:
        return bus.call(PLAN, task, repeat=True)
    except ServiceBusyError as error:
        return error


def test_callers_told_busy_see_nothing_planned_the_others_get_theirs_once(
    stack: Launcher,
) -> None:
    """``CALLERS`` 16-target plans at once, each asked again after 0.2 s if
    unanswered: a caller told busy finds its request neither planned nor
    published; each plan published is its caller's answer, published once."""
    requested: list[str] = []
    published: list[bytes] = []
    with Bus.connect(stack.config) as bus:
        subscribers = [
            bus.session.declare_subscriber(
                f"{NAMESPACE}/{PLAN_REQUEST_TOPIC}",
                lambda s: requested.append(
                    json.loads(s.payload.to_bytes())["request_id"]
                ),
            ),
            bus.session.declare_subscriber(
                f"{NAMESPACE}/{TRAJECTORY_TOPIC}",
                lambda s: published.append(s.payload.to_bytes()),
            ),
        ]
        try:
            time.sleep(0.5)  # let the router learn of the subscribers
            asked = tasks()
            with ThreadPoolExecutor(CALLERS) as pool:
                outcomes = list(pool.map(lambda t: ask(bus, t), asked))
            time.sleep(0.5)  # publications come before their answers
        finally:
            for subscriber in subscribers:
                subscriber.undeclare()  # type: ignore[no-untyped-call]
    answered = [
        (t.request_id, o)
        for t, o in zip(asked, outcomes, strict=True)
        if isinstance(o, Trajectory)
    ]
    refused = [o for o in outcomes if isinstance(o, ServiceBusyError)]
    assert sorted(requested) == sorted(i for i, _ in answered)  # each once
    assert sorted(published) == sorted(o.to_json().encode() for _, o in answered)
    # One runs, usually one waits (unless all came before the worker took
    # the first from the queue); the rest are refused.
    assert answered and refused
