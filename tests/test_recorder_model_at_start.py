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
from collections.abc import Callable, Iterator

import pytest

from armplan.launch import Launcher, free_endpoint
from services.fit import fit_model, save_model
from services.fit.model_state import digest
from services.recorder import RecorderOptions
from services.recorder.model_at_start import ASK_TIMEOUT
from services.recorder.replay import replay_items
from services.recorder.service import Recorder
from shared.bus import Bus, load_config
from shared.demos import synthesize
from shared.messages import MotionModel
from shared.recording import read_records
from shared.recording.rotation import RotationPolicy

MODEL_CHANNEL = "armplan/fit/model"


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 5), not the shipped one."""
    return fit_model(synthesize(5, subjects=3, trials=1), bins=10)


def record(
    bus: Bus,
    output: pathlib.Path,
    keys: tuple[str, ...],
    rotation: RotationPolicy | None = None,
    then: Callable[[], None] = lambda: None,
) -> Recorder:
    """Record ``keys`` until the model's ask ended and ``then`` ran; stopped."""
    options = RecorderOptions(
        output=output, keys=keys, rotation=rotation or RotationPolicy()
    )
    recorder = Recorder(bus, options).start()
    if recorder.model_at_start is not None:
        recorder.model_at_start.join(ASK_TIMEOUT + 5.0)
    time.sleep(0.3)  # the answer reaches the writer
    then()
    recorder.stop()
    return recorder


@pytest.fixture
def lab_fit(lab_model: MotionModel, tmp_path: pathlib.Path) -> Iterator[Launcher]:
    """A router and the fit service serving ``lab_model``."""
    model_file = tmp_path / "lab.json"
    save_model(lab_model, model_file)
    state = tmp_path / "state"
    state.mkdir()
    config = load_config(endpoints=(free_endpoint(),))
    args = {"fit": ["--model", str(model_file), "--state-dir", str(state)]}
    with Launcher(config, ["fit"], log=subprocess.DEVNULL, service_args=args) as up:
        yield up


def test_the_model_served_at_the_start_is_recorded(
    lab_model: MotionModel, lab_fit: Launcher, tmp_path: pathlib.Path
) -> None:
    """The fit service started before the recorder: its model is in the
    file, on ``armplan/fit/model`` as a typed ``MotionModel``, the model it
    serves (same digest), once; not on ``fit/model/update`` (nothing was
    published while it recorded)."""
    out = tmp_path / "session.mcap"
    with Bus.connect(lab_fit.config) as bus:
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


def test_each_rotated_file_holds_the_model_and_a_replay_sends_none(
    lab_model: MotionModel, lab_fit: Launcher, tmp_path: pathlib.Path
) -> None:
    """A rotating recording: every file starts with the model (each file
    stands alone), the first as asked, the later ones carried over. A
    replay of the files sends the published messages, not the model: it
    was an answer, and a put on the fit service's queryable key reaches no
    one."""
    out = tmp_path / "rot.mcap"
    filler = b'{"note": "' + b"x" * 3000 + b'"}'

    def publish(bus: Bus) -> None:
        for _ in range(12):
            bus.session.put(bus.key("plan/filler"), filler)
            time.sleep(0.02)

    with Bus.connect(lab_fit.config) as bus:
        recorder = record(
            bus,
            out,
            ("plan/**", "fit/model/update"),
            RotationPolicy(max_bytes=8000),
            lambda: publish(bus),
        )
    parts = recorder.sink.paths
    assert len(parts) >= 3
    for part in parts:
        models = [r for r in read_records(part) if r.topic == MODEL_CHANNEL]
        assert len(models) == 1, part
        assert models[0].schema == "MotionModel"
        assert digest(MotionModel.model_validate(models[0].data)) == digest(lab_model)
    items = list(replay_items(parts))
    assert len(items) == 12
    assert {item.path for item in items} == {"plan/filler"}
