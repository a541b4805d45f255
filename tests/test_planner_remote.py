"""Which stage services a remote plan needs."""

from __future__ import annotations

import pytest

from services.planner.remote import needed_routes
from shared.bus.routes import DECIDE, IK_PATH, TIMING
from shared.messages import Method, PlanRequest, WristPath

REACH = {"targets": [{"position": (0.12, -0.10, 0.05)}]}
PATH = WristPath(
    arm="right", times=[0.0, 0.01], positions=[(0.1, -0.1, 0.0), (0.1, -0.1, 0.01)]
)


@pytest.mark.parametrize(
    "method,routes",
    [
        (Method.MP, [DECIDE, IK_PATH, TIMING]),
        (Method.LEAST_NORM, [IK_PATH, TIMING]),
        (Method.SINGLE, [IK_PATH, TIMING]),
    ],
)
def test_targets_need_timing_and_mp_needs_the_decision(
    method: Method, routes: list[object]
) -> None:
    """Only method mp asks decide; a task of targets is timed by the service."""
    request = PlanRequest.model_validate({**REACH, "method": method})
    assert needed_routes(request) == routes


def test_a_timed_wrist_path_needs_no_timing_service() -> None:
    """A wrist path keeps its own times: decide and ik only."""
    assert needed_routes(PlanRequest(wrist_path=PATH)) == [DECIDE, IK_PATH]
