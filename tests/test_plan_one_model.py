"""A plan's decisions come from one motion model, and say which.

The planner asks the decide stage once per reach: a fit landing between two
of those queries (the decide service swaps the new model in between two
requests) used to split a plan between two models, and no decision said
which model made it. Here the in-process stages' model is swapped between
two decide calls, deterministically.
"""

from __future__ import annotations

import pytest

from services.decide import Decider
from services.fit import default_model, fit_model
from services.fit.model_state import digest
from services.planner.pipeline import plan
from services.planner.stages import LocalStages
from shared.demos import synthesize
from shared.errors import ModelChangedError
from shared.messages import DecideRequest, Decision, MotionModel, PlanRequest

#: Three reaches: three decide queries per plan.
TASK = PlanRequest.model_validate(
    {
        "targets": [
            {"position": (0.12, -0.1, 0.05)},
            {"position": (0.14, -0.06, 0.1)},
            {"position": (0.1, -0.12, 0.0)},
        ]
    }
)


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 9), not the shipped one."""
    return fit_model(synthesize(9, subjects=3, trials=1), bins=10)


class SwappingStages(LocalStages):
    """Local stages that swap between two models (a fit landing) right
    after the decide calls numbered in ``swap_after`` (from 1)."""

    def __init__(self, first: MotionModel, second: MotionModel, swap_after: set[int]):
        super().__init__(first)
        self.deciders = [self.decider, Decider(second)]
        self.swap_after = swap_after
        self.calls = 0

    def decide(self, request: DecideRequest) -> Decision:
        decision = super().decide(request)
        self.calls += 1
        if self.calls in self.swap_after:
            self.deciders.reverse()
            self.decider = self.deciders[0]
        return decision


def test_each_decision_names_its_model(lab_model: MotionModel) -> None:
    result = plan(TASK, LocalStages(lab_model))
    assert [d.model for d in result.decisions] == [digest(lab_model)] * 3
    assert digest(lab_model) != digest(default_model())


def test_a_plan_split_by_a_swap_is_made_again_with_one_model(
    lab_model: MotionModel,
) -> None:
    """Swapped after the first reach's decision: planned once more, all with
    the new model, as a plan with that model alone."""
    stages = SwappingStages(default_model(), lab_model, swap_after={1})
    result = plan(TASK, stages)
    assert stages.calls == 6  # the split plan (3) and the new one (3)
    assert [d.model for d in result.decisions] == [digest(lab_model)] * 3
    assert result.trajectory == plan(TASK, LocalStages(lab_model)).trajectory


def test_a_plan_split_twice_is_refused(lab_model: MotionModel) -> None:
    stages = SwappingStages(default_model(), lab_model, swap_after={1, 4})
    with pytest.raises(ModelChangedError) as raised:
        plan(TASK, stages)
    assert raised.value.kind == "model_changed"
    assert set(raised.value.models) == {digest(default_model()), digest(lab_model)}


def test_the_decision_json_leaves_out_an_unknown_model(lab_model: MotionModel) -> None:
    """Old recordings (no ``model``) still read; none set: the JSON is as before."""
    decision = plan(TASK, LocalStages(lab_model)).decisions[0]
    old = decision.model_copy(update={"model": None})
    assert '"model"' not in old.to_json()
    assert Decision.model_validate_json(old.to_json()).model is None
    assert Decision.model_validate_json(decision.to_json()) == decision
