"""Once the launcher says ready, decide decides with the fit service's model.

Real router, fit and decide processes on a free loopback port; fit's state
file holds a lab model (a restart with a kept model). Fit takes longer to
start than decide (it reads and checks that file): started together, decide
came alive with the shipped model, the launcher saw both tokens and said
ready, and decide swapped fit's model in only a moment later, so the first
plan after "ready" was decided (partly) with the shipped model. Now decide
is started once fit is alive and gets its model before its own token.
"""

from __future__ import annotations

import pathlib

import pytest

from armplan.launch import Launcher, free_endpoint
from services.decide import Decider
from services.fit import default_model, fit_model
from services.fit.model_file import save_model
from services.fit.model_state import digest, state_file
from services.planner.pipeline import plan
from services.planner.stages import decide
from shared.bus import Bus, load_config
from shared.bus.routes import DECIDE
from shared.demos import synthesize
from shared.messages import DecideRequest, Decision, MotionModel, PlanRequest


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 9), not the shipped one;
    fine enough (48 bins) that fit takes about a second to check it at start."""
    return fit_model(synthesize(9, subjects=3, trials=1), bins=48)


@pytest.fixture(scope="module")
def request_() -> DecideRequest:
    """The wrist path of a reach from rest (right arm)."""
    reach = PlanRequest.model_validate({"targets": [{"position": (0.12, -0.1, 0.05)}]})
    return DecideRequest(path=plan(reach).wrist_paths[0])


def decided(model: MotionModel, request: DecideRequest) -> Decision:
    return decide(Decider(model), request)[0]


@pytest.mark.parametrize("names", [["fit", "decide"], ["decide", "fit"]])
def test_ready_means_decide_serves_the_kept_model(
    tmp_path: pathlib.Path,
    lab_model: MotionModel,
    request_: DecideRequest,
    names: list[str],
) -> None:
    """The first decision after start is the kept model's, whatever order
    the services are named in, and says so (``Decision.model``)."""
    wanted = decided(lab_model, request_)
    assert wanted != decided(default_model(), request_)  # the test can fail
    config = load_config(endpoints=(free_endpoint(),))
    save_model(lab_model, state_file(tmp_path, config.namespace))
    fit_args = ["--state-dir", str(tmp_path)]
    with (
        (tmp_path / "services.log").open("w") as log,
        Launcher(config, names, log=log, service_args={"fit": fit_args}) as up,
        Bus.connect(up.config) as bus,
    ):
        first = bus.call(DECIDE, request_)
    assert first.model == digest(lab_model)  # the digest fit and decide log
    assert first == wanted
