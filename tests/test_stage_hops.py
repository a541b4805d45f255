"""The stage requests the services benchmark sends are the planner's own."""

from __future__ import annotations

import pytest

from armplan.bench.service_latency import one_second_reach
from armplan.bench.stage_hops import STAGES, stage_requests
from services.planner import stages, timing_stage
from services.planner.pipeline import plan
from shared.messages import Decision, JointPath, PlanRequest


def test_the_three_requests_replayed_give_the_plan_itself() -> None:
    """decide, then ik with that decision, then timing: the same trajectory as
    the planner's, bit for bit (but for the point times the planner moves to
    its decision), and each request carries the previous reply."""
    request = one_second_reach()
    sent = stage_requests(request)
    assert list(sent) == list(STAGES)
    decision, _ = stages.decide(stages.default_decider(), sent["decide"])
    assert isinstance(decision, Decision)
    assert sent["ik"].decision == decision  # type: ignore[attr-defined]
    joint_path = stages.path_ik(sent["ik"])  # type: ignore[arg-type]
    assert isinstance(joint_path, JointPath)
    assert sent["timing"].segments[0].joint_path == joint_path  # type: ignore[attr-defined]
    trajectory = timing_stage.timing(sent["timing"])  # type: ignore[arg-type]
    planned = plan(request)
    assert trajectory.point_times == [planned.decisions[0].trajectory_times]
    plain = trajectory.model_copy(update={"point_times": None})
    assert plain.to_json() == planned.trajectory.to_json()


@pytest.mark.parametrize(
    ("change", "missing"),
    [({"method": "least-norm"}, "decide"), ({"method": "single"}, "decide")],
)
def test_a_plan_without_every_stage_is_refused(
    change: dict[str, str], missing: str
) -> None:
    """A baseline method makes no decision: nothing to send to decide."""
    request = PlanRequest.model_validate(
        {**one_second_reach().model_dump(mode="json"), **change}
    )
    with pytest.raises(ValueError, match=missing):
        stage_requests(request)


def test_a_timed_wrist_path_is_refused() -> None:
    """A timed wrist path keeps its times: the planner calls no timing stage."""
    wrist = plan(one_second_reach()).wrist_paths[0]
    request = PlanRequest.model_validate({"wrist_path": wrist.model_dump(mode="json")})
    with pytest.raises(ValueError, match="timing"):
        stage_requests(request)
