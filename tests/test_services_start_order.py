"""The fit service's start model reaches whoever starts first, fit or decide.

Real processes on a free loopback port. It used to be a race: fit
published its start model before its token, and decide asked for fit's
model once, subscribed to its publications only after; in 2 runs of 8 of
``armplan up --model FILE`` decide planned with the shipped model for good.
"""

from __future__ import annotations

import pathlib
import threading

import pytest
import zenoh

from armplan.launch import Launcher, free_endpoint
from services.fit import fit_model
from services.fit.model_file import save_model
from shared.bus import Bus, NoArguments, load_config
from shared.bus.routes import FIT_MODEL, MODEL_TOPIC
from shared.demos import synthesize
from shared.errors import ArmplanError
from shared.messages import MotionModel, parse


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 9), not the shipped one."""
    return fit_model(synthesize(9, subjects=3, trials=1), bins=10)


@pytest.fixture()
def model_file(tmp_path: pathlib.Path, lab_model: MotionModel) -> pathlib.Path:
    path = tmp_path / "lab_model.json"
    save_model(lab_model, path)
    return path


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
