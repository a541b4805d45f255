"""A recording started after the fit service holds the model served then.

Real Zenoh: a router and the fit service as processes (serving a lab
model fitted to seeded synthetic demonstrations), the recorder in this
process, the MCAP file read back.
"""

from __future__ import annotations

import logging
import pathlib
import subprocess
import time

import pytest

from armplan.launch import Launcher, free_endpoint
from services.fit import fit_model, save_model
from services.fit.model_state import digest
from services.recorder import RecorderOptions
from services.recorder.model_at_start import ASK_TIMEOUT
from services.recorder.service import Recorder
from shared.bus import Bus, load_config
from shared.demos import synthesize
from shared.messages import MotionModel
from shared.recording import read_records

MODEL_CHANNEL = "armplan/fit/model"


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 5), not the shipped one."""
    return fit_model(synthesize(5, subjects=3, trials=1), bins=10)


def record(bus: Bus, output: pathlib.Path, keys: tuple[str, ...]) -> Recorder:
    """Record ``keys`` until the model's ask ended; stopped, file closed."""
    recorder = Recorder(bus, RecorderOptions(output=output, keys=keys)).start()
    if recorder.model_at_start is not None:
        recorder.model_at_start.join(ASK_TIMEOUT + 5.0)
    time.sleep(0.3)  # the answer reaches the writer
    recorder.stop()
    return recorder


def test_the_model_served_at_the_start_is_recorded(
    lab_model: MotionModel, tmp_path: pathlib.Path
) -> None:
    """The fit service started before the recorder: its model is in the
    file, on ``armplan/fit/model`` as a typed ``MotionModel``, the model it
    serves (same digest), once; not on ``fit/model/update`` (nothing was
    published while it recorded)."""
    model_file = tmp_path / "lab.json"
    save_model(lab_model, model_file)
    state = tmp_path / "state"
    state.mkdir()
    config = load_config(endpoints=(free_endpoint(),))
    args = {"fit": ["--model", str(model_file), "--state-dir", str(state)]}
    with (
        Launcher(config, ["fit"], log=subprocess.DEVNULL, service_args=args) as up,
        Bus.connect(up.config) as bus,
    ):
        out = tmp_path / "session.mcap"
        recorder = record(bus, out, ("plan/**", "fit/model/update"))
    assert recorder.model_at_start is not None and recorder.model_at_start.recorded
    records = list(read_records(out))
    models = [r for r in records if r.topic == MODEL_CHANNEL]
    assert len(models) == 1
    assert models[0].schema == "MotionModel"
    assert digest(MotionModel.model_validate(models[0].data)) == digest(lab_model)
    assert not [r for r in records if r.topic.endswith("fit/model/update")]


def test_no_model_is_asked_without_the_model_topic_or_a_fit_service(
    tmp_path: pathlib.Path, caplog: pytest.LogCaptureFixture
) -> None:
    """Keys without ``fit/model/update``: nothing is asked. No fit service
    alive: it is not asked either (no wait for an answer that cannot come),
    and the file has no model channel."""
    config = load_config(endpoints=(free_endpoint(),))
    caplog.set_level(logging.INFO, logger="armplan.recorder")
    with Launcher(config, []) as up, Bus.connect(up.config) as bus:
        without = record(bus, tmp_path / "plan-only.mcap", ("plan/**",))
        alone = record(bus, tmp_path / "alone.mcap", ("fit/model/update",))
    assert without.model_at_start is None
    assert alone.model_at_start is not None and not alone.model_at_start.recorded
    assert "no fit service alive" in caplog.text
    for name in ("plan-only.mcap", "alone.mcap"):
        topics = {r.topic for r in read_records(tmp_path / name)}
        assert MODEL_CHANNEL not in topics
