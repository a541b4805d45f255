"""The fit service's start model reaches whoever starts first, fit or decide.

Real processes on a free loopback port; in the decide tests the router and
the decide service start first (so decide finds no fit service and starts
with the shipped model), then a fit service with a lab model. It used to be
a race: fit published its start model before its token, and decide asked
for fit's model once, subscribed to its publications only after; in 2 runs
of 8 of ``armplan up --model FILE`` decide planned with the shipped model
for good.
"""

from __future__ import annotations

import pathlib
import threading
import time
from collections.abc import Callable, Iterator

import pytest
import zenoh

from armplan.launch import Launcher, free_endpoint
from services.decide import Decider
from services.fit import default_model, fit_model
from services.fit.model_file import save_model
from services.fit.model_state import digest
from services.planner.pipeline import plan
from services.planner.stages import decide
from shared.bus import Bus, Endpoint, NoArguments, ServiceHost, load_config
from shared.bus.routes import DECIDE, FIT_MODEL, MODEL_TOPIC
from shared.demos import synthesize
from shared.errors import ArmplanError
from shared.messages import DecideRequest, Decision, MotionModel, PlanRequest, parse

#: Longest wait for decide to take up fit's model [s].
FOLLOW_WAIT = 30.0


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 9), not the shipped one."""
    return fit_model(synthesize(9, subjects=3, trials=1), bins=10)


@pytest.fixture(scope="module")
def request_() -> DecideRequest:
    """The wrist path of a reach from rest (right arm)."""
    reach = PlanRequest.model_validate({"targets": [{"position": (0.12, -0.1, 0.05)}]})
    return DecideRequest(path=plan(reach).wrist_paths[0])


@pytest.fixture()
def model_file(tmp_path: pathlib.Path, lab_model: MotionModel) -> pathlib.Path:
    path = tmp_path / "lab_model.json"
    save_model(lab_model, path)
    return path


@pytest.fixture()
def decide_first(
    tmp_path: pathlib.Path, model_file: pathlib.Path
) -> Iterator[tuple[Launcher, pathlib.Path]]:
    """Router and decide running, fit not yet (``--model`` the lab model);
    and the children's log file."""
    config = load_config(endpoints=(free_endpoint(),))
    fit_args = ["--model", str(model_file), "--state-dir", str(tmp_path)]
    log_path = tmp_path / "services.log"
    with (
        log_path.open("w") as log,
        Launcher(config, ["decide"], log=log, service_args={"fit": fit_args}) as up,
    ):
        yield up, log_path


def decided(model: MotionModel, request: DecideRequest) -> Decision:
    return decide(Decider(model), request)[0]


def until(check: Callable[[], bool], timeout: float) -> bool:
    """Whether ``check`` came true within ``timeout`` [s] (asked every 0.1 s)."""
    deadline = time.monotonic() + timeout
    while not (ok := check()) and time.monotonic() < deadline:
        time.sleep(0.1)
    return ok


def test_the_two_models_decide_differently(
    lab_model: MotionModel, request_: DecideRequest
) -> None:
    """So a decide answer tells which model decide uses (the tests can fail)."""
    assert decided(lab_model, request_) != decided(default_model(), request_)


def test_decide_started_before_fit_takes_up_fits_model(
    decide_first: tuple[Launcher, pathlib.Path],
    lab_model: MotionModel,
    request_: DecideRequest,
) -> None:
    """decide starts with the shipped model; once fit starts with ``--model``,
    decide decides with that model and logs its digest, as fit does."""
    up, log_path = decide_first
    wanted = decided(lab_model, request_)
    with Bus.connect(up.config) as bus:
        assert bus.call(DECIDE, request_) == decided(default_model(), request_)
        up.start_service("fit")
        assert bus.wait_alive(["fit"], 60.0) == []
        assert until(lambda: bus.call(DECIDE, request_) == wanted, FOLLOW_WAIT)
    log = log_path.read_text()
    assert f"serving model {digest(default_model())} " in log
    assert f"swapped in model {digest(lab_model)} " in log
    assert f"serving model {digest(lab_model)} " in log  # fit's own line


def test_decide_asks_a_fit_service_that_appears_after_it(
    decide_first: tuple[Launcher, pathlib.Path],
    lab_model: MotionModel,
    request_: DecideRequest,
) -> None:
    """A fit service whose publication decide never gets (this one publishes
    nothing) is asked for its model when its token appears."""
    up, _ = decide_first
    wanted = decided(lab_model, request_)
    with Bus.connect(up.config) as bus:
        assert bus.call(DECIDE, request_) != wanted
        served = [Endpoint(FIT_MODEL, lambda _: lab_model)]
        with ServiceHost(bus, "fit", served):
            assert until(lambda: bus.call(DECIDE, request_) == wanted, FOLLOW_WAIT)


def test_fit_answers_whoever_got_its_start_model(
    tmp_path: pathlib.Path, model_file: pathlib.Path, lab_model: MotionModel
) -> None:
    """Fit publishes its start model once its queryables and token are
    declared: asked at once by the one who got the publication, it answers
    that model (it used to publish about 13 ms before; such a query was told
    the fit service is unavailable)."""
    config = load_config(endpoints=(free_endpoint(),))
    fit_args = ["--model", str(model_file), "--state-dir", str(tmp_path)]
    answers: list[MotionModel | str] = []
    answered = threading.Event()

    with (
        Launcher(config, [], service_args={"fit": fit_args}) as up,
        Bus.connect(up.config) as bus,
    ):

        def ask() -> None:
            try:
                answers.append(bus.call(FIT_MODEL, NoArguments()))
            except ArmplanError as error:
                answers.append(error.message)
            answered.set()

        def on_model(sample: zenoh.Sample) -> None:  # on Zenoh's thread
            if not answered.is_set() and not answers:
                answers.append(parse(MotionModel, sample.payload.to_bytes()))
                threading.Thread(target=ask).start()

        models = bus.session.declare_subscriber(bus.key(MODEL_TOPIC), on_model)
        up.start_service("fit")
        assert answered.wait(60.0), "fit's start model was not published"
        models.undeclare()  # type: ignore[no-untyped-call]
    assert answers == [lab_model, lab_model]
