"""The fit and decide services as real processes: fitted models reach decide live."""

from __future__ import annotations

import pathlib
import signal
import subprocess
import time
from collections.abc import Iterator

import pytest

from armplan.launch import Launcher, free_endpoint
from services.decide import Decider
from services.fit import default_model, fit_model
from services.fit.demo_dir import DEMOS_DIR_ENV
from services.planner.pipeline import plan
from services.planner.stages import decide
from shared.bus import Bus, NoArguments, load_config
from shared.bus.routes import DECIDE, FIT, FIT_MODEL, MODEL_TOPIC
from shared.bus.topics import topic_message
from shared.demos import read_demos, synthesize, write_demos
from shared.errors import DemoFileError, InvalidInputError, TooFewSamplesError
from shared.messages import (
    DecideRequest,
    Decision,
    FitRequest,
    MotionModel,
    PlanRequest,
)

DEMOS = "demos.mcap"
FIT_REQUEST = FitRequest(files=[DEMOS], bins=10)
TINY = "three_reaches.mcap"


@pytest.fixture(scope="module")
def demos_dir(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """A directory holding a small synthetic demonstration file (seed 9)."""
    root = tmp_path_factory.mktemp("demos")
    write_demos(root / DEMOS, synthesize(9, subjects=3, trials=1))
    write_demos(root / TINY, synthesize(9, subjects=1, trials=1, points=(1, 2, 3)))
    return root


@pytest.fixture(scope="module")
def stack(demos_dir: pathlib.Path) -> Iterator[Launcher]:
    """Router, fit (reading ``demos_dir``) and decide on a free port."""
    config = load_config(endpoints=(free_endpoint(),))
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(DEMOS_DIR_ENV, str(demos_dir))
        with Launcher(config, ["fit", "decide"], log=subprocess.DEVNULL) as stack:
            yield stack


@pytest.fixture(scope="module")
def bus(stack: Launcher) -> Iterator[Bus]:
    with Bus.connect(stack.config) as bus:
        yield bus


@pytest.fixture(scope="module")
def request_() -> DecideRequest:
    """The wrist path of a reach from rest (right arm)."""
    reach = PlanRequest.model_validate({"targets": [{"position": (0.12, -0.1, 0.05)}]})
    return DecideRequest(path=plan(reach).wrist_paths[0])


def decided(model: MotionModel, request: DecideRequest) -> Decision:
    return decide(Decider(model), request)[0]


def wait_for_decision(
    bus: Bus, request: DecideRequest, wanted: Decision, timeout: float = 30.0
) -> Decision:
    """Ask decide until it answers ``wanted`` (a publication arrives
    asynchronously) or ``timeout`` [s] passes; the last answer."""
    deadline = time.monotonic() + timeout
    while (got := bus.call(DECIDE, request)) != wanted and time.monotonic() < deadline:
        time.sleep(0.1)
    return got


def test_the_model_topic_carries_the_model_message() -> None:
    """The recorder gives fit/model/update the MotionModel schema."""
    assert topic_message(MODEL_TOPIC) is MotionModel


def test_fit_serves_the_default_model_and_decide_uses_it(
    bus: Bus, request_: DecideRequest
) -> None:
    """Before any fit: the shipped model, and decide's answer is its decision."""
    assert bus.call(FIT_MODEL, NoArguments()) == default_model()
    assert bus.call(DECIDE, request_) == decided(default_model(), request_)


@pytest.mark.parametrize(
    "files,error,words",
    [
        (["../outside.mcap"], InvalidInputError, "outside the fit service's"),
        (["/etc/hostname.mcap"], InvalidInputError, "outside the fit service's"),
        (["notes.txt"], InvalidInputError, "must be an .mcap file"),
        (["missing.mcap"], DemoFileError, "no such"),
        ([TINY], TooFewSamplesError, "3 trials are too few to fit"),
    ],
    ids=["parent", "absolute", "not-mcap", "missing", "tiny"],
)
def test_a_bad_fit_request_is_refused_and_the_model_stays(
    bus: Bus, files: list[str], error: type[Exception], words: str
) -> None:
    """Typed errors naming the file; the served model is unchanged."""
    before = bus.call(FIT_MODEL, NoArguments())
    with pytest.raises(error, match=words):
        bus.call(FIT, FitRequest(files=files))
    assert bus.call(FIT_MODEL, NoArguments()) == before


def test_decide_picks_up_a_model_fit_publishes(
    stack: Launcher, bus: Bus, demos_dir: pathlib.Path, request_: DecideRequest
) -> None:
    """A fit returns the in-process model, fit serves it from then on, and the
    running decide service decides with it (no restart; its PID is the same)."""
    pid = stack.services["decide"].pid
    expected = fit_model(read_demos(demos_dir / DEMOS), bins=10, sources=[DEMOS])
    wanted = decided(expected, request_)
    assert wanted != decided(default_model(), request_)  # the test can fail
    assert bus.call(FIT, FIT_REQUEST, timeout=300.0) == expected
    assert bus.call(FIT_MODEL, NoArguments()) == expected
    assert wait_for_decision(bus, request_, wanted) == wanted
    assert stack.services["decide"].pid == pid


def test_a_restarted_decide_starts_with_fits_current_model(
    stack: Launcher, bus: Bus, demos_dir: pathlib.Path, request_: DecideRequest
) -> None:
    """decide asks fit for its model at start: after a restart it still
    decides with the fitted model, not the shipped one."""
    if bus.call(FIT_MODEL, NoArguments()) == default_model():
        bus.call(FIT, FIT_REQUEST, timeout=300.0)
    fitted = bus.call(FIT_MODEL, NoArguments())
    stack.services["decide"].signal(signal.SIGTERM)
    stack.services["decide"].process.wait(30.0)
    stack.start_service("decide")
    assert bus.wait_alive(["decide"], 60.0) == []
    assert bus.call(DECIDE, request_) == decided(fitted, request_)
