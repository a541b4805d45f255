"""How long the planner waits for each stage: its caller's time, within bounds.

A real router and bus (the planner's stages are queries on it). Each stage
waits what the caller has left less the margin for the answer; longer than
the bus's timeout when the caller waits longer (a ``--timeout 30`` plan
with a stage queued 7 s failed at 5 s), but never past ``STAGE_LIMIT``
(a stage that hangs while connected would hold a planner worker for a
caller's day-long timeout).
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest

from armplan.launch import free_endpoint
from services.planner.remote import STAGE_LIMIT, RemoteStages, stage_margin
from shared.bus import Bus, BusConfig, open_router
from shared.bus.deadline import Due, serving_until


@pytest.fixture(scope="module")
def stages() -> Iterator[RemoteStages]:
    config = BusConfig(endpoints=(free_endpoint(),), timeout=5.0)
    with open_router(config), Bus.connect(config) as bus:
        yield RemoteStages(bus)


def wait_for(stages: RemoteStages, budget: float | None) -> float:
    """The stage wait [s] while serving a caller with ``budget`` [s] left."""
    due = None if budget is None else Due(time.monotonic() + budget, budget)
    with serving_until(due):
        return stages._wait()


@pytest.mark.parametrize(
    ("budget", "expected"),
    [
        (None, 5.0),  # no caller's deadline: the bus's timeout
        (2.0, 2.0 - stage_margin(2.0)),  # shorter than the bus's
        (30.0, 30.0 - stage_margin(30.0)),  # longer: the caller asked
        (86_400.0, STAGE_LIMIT),  # a day: no longer than the limit
    ],
    ids=["none", "short", "long", "day"],
)
def test_a_stage_waits_its_callers_time_within_the_limit(
    stages: RemoteStages, budget: float | None, expected: float
) -> None:
    assert wait_for(stages, budget) == pytest.approx(expected, abs=0.05)


def test_a_caller_gone_leaves_the_bus_timeout(stages: RemoteStages) -> None:
    """Past the caller's deadline the plan goes on for a repeat: the bus's wait."""
    with serving_until(Due(time.monotonic() - 1.0, 1.0)):
        assert stages._wait() == 5.0
