"""The decide service's live model: compiled once per model, closed at stop.

Real Zenoh: a router on a free loopback port, the model followed in this
process (``LiveModel``) or the decide service as a process.
"""

from __future__ import annotations

import dataclasses
import logging
import pathlib
import time
from collections.abc import Callable

import pytest

from armplan.launch import Launcher, free_endpoint
from services.decide.live_model import LiveModel
from services.fit import default_model, fit_model
from shared.bus import Bus, load_config
from shared.bus.routes import MODEL_TOPIC
from shared.demos import synthesize
from shared.messages import MotionModel

#: The router of the max_payload test (a fixed loopback port).
#: Longest wait for a publication to be taken up [s].
FOLLOW_WAIT = 30.0


@pytest.fixture(scope="module")
def lab_model() -> MotionModel:
    """A model fitted to synthetic demonstrations (seed 9), not the shipped one."""
    return fit_model(synthesize(9, subjects=3, trials=1), bins=10)


def until(check: Callable[[], bool], timeout: float) -> bool:
    """Whether ``check`` came true within ``timeout`` [s] (asked every 0.05 s)."""
    deadline = time.monotonic() + timeout
    while not (ok := check()) and time.monotonic() < deadline:
        time.sleep(0.05)
    return ok


def test_a_published_model_already_served_is_not_compiled_again(
    lab_model: MotionModel,
) -> None:
    """No fit service: it starts on the shipped model (one compile). The lab
    model published once is compiled and swapped in; published five times
    more it is not compiled again (each was, about 44 ms on Zenoh's thread,
    then dropped); the shipped model published after is (in order, so its
    swap shows the duplicates were handled)."""
    config = load_config(endpoints=(free_endpoint(),))
    with (
        Launcher(config, []) as up,
        Bus.connect(up.config) as bus,
        Bus.connect(up.config) as fit,
    ):
        live = LiveModel(bus)
        try:
            assert (live.compiled, live.updates) == (1, 0)
            fit.publish(MODEL_TOPIC, lab_model)
            assert until(lambda: live.updates == 1, FOLLOW_WAIT)
            assert live.compiled == 2
            for _ in range(5):
                fit.publish(MODEL_TOPIC, lab_model)
            fit.publish(MODEL_TOPIC, default_model())
            assert until(lambda: live.updates == 2, FOLLOW_WAIT)
            assert live.compiled == 3
            assert live.decider.model == default_model()
        finally:
            live.close()


def test_the_decide_service_stops_following_before_its_session_closes(
    tmp_path: pathlib.Path,
) -> None:
    """Stopped (SIGTERM), the decide service undeclares its subscribers
    after its queryables, before its session closes (``LiveModel.close``
    was never called), and exits cleanly."""
    config = load_config(endpoints=(free_endpoint(),))
    log_path = tmp_path / "services.log"
    with log_path.open("w") as log, Launcher(config, ["decide"], log=log) as up:
        decide = up.services["decide"]
    text = log_path.read_text()
    assert "Traceback" not in text
    stopped = text.index("service decide stopped")
    assert text.index("stopped following the fit service's model") > stopped
    assert decide.exit_code() == 0


def test_a_published_model_over_max_payload_is_ignored_unread(
    lab_model: MotionModel, caplog: pytest.LogCaptureFixture
) -> None:
    """A 60 MB publication on ``fit/model/update`` (a list of empty
    objects) held over 10 GB of the decide service's memory while it was
    parsed. One over the bus's ``max_payload`` is now ignored unread, with a
    warning naming its size and the limit; the next model under it is
    swapped in."""
    large = fit_model(synthesize(9, subjects=3, trials=1), bins=20)
    assert len(lab_model.to_json()) < len(large.to_json())
    limit = len(large.to_json()) - 1
    config = dataclasses.replace(
        load_config(endpoints=(free_endpoint(),)), max_payload=limit
    )
    with (
        Launcher(config, []) as up,
        Bus.connect(up.config) as bus,
        Bus.connect(up.config) as fit,
        caplog.at_level(logging.WARNING, logger="armplan.decide"),
    ):
        live = LiveModel(bus)
        try:
            fit.publish(MODEL_TOPIC, large)
            fit.publish(MODEL_TOPIC, lab_model)
            assert until(lambda: live.updates >= 1, FOLLOW_WAIT)
            assert live.decider.model == lab_model
            assert (live.compiled, live.updates) == (2, 1)  # the large one unread
        finally:
            live.close()
    (warning,) = [
        r.getMessage() for r in caplog.records if "max_payload" in r.getMessage()
    ]
    assert f"{len(large.to_json())} bytes" in warning and f"{limit} bytes" in warning
