"""The fit service's current model: one fit at a time, none installed late.

A real router and bus on loopback; the model is fitted in this process.
"""

from __future__ import annotations

import pathlib
import threading
import time
from collections.abc import Iterator

import pytest

from armplan.launch import free_endpoint
from services.fit.current_model import CurrentModel
from services.fit.demo_dir import DEMOS_DIR_ENV
from shared.bus import Bus, BusConfig, NoArguments, open_router
from shared.bus.deadline import Due, serving_until
from shared.demos import synthesize, write_demos
from shared.errors import RequestTimeoutError, ServiceBusyError
from shared.messages import FitRequest, MotionModel

DEMOS = "demos.mcap"


@pytest.fixture()
def current(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[CurrentModel]:
    """A current model (the shipped one) on a bus, demonstrations in tmp_path."""
    write_demos(tmp_path / DEMOS, synthesize(9, subjects=3, trials=1))
    monkeypatch.setenv(DEMOS_DIR_ENV, str(tmp_path))
    config = BusConfig(endpoints=(free_endpoint(),))
    with open_router(config), Bus.connect(config) as bus:
        yield CurrentModel(bus)


def test_a_fit_its_caller_stopped_waiting_for_is_not_installed(
    current: CurrentModel,
) -> None:
    """Fitted for a caller whose 0.2 s ran out before the fit ended: refused
    as a timeout, and the model served stays the one before. (It used to be
    installed and published, changing every plan, 36 s after its caller was
    told it timed out.)"""
    before = current.get(NoArguments())
    gone = Due(at=time.monotonic() - 1.0, budget=0.2)
    with serving_until(gone), pytest.raises(RequestTimeoutError, match="fit"):
        current.fit(FitRequest(files=[DEMOS], bins=10))
    assert current.get(NoArguments()) == before
    fitted = current.fit(FitRequest(files=[DEMOS], bins=10))  # no deadline
    assert current.get(NoArguments()) == fitted != before


def test_a_second_fit_while_one_runs_is_refused_at_once(
    current: CurrentModel,
) -> None:
    """While a fit runs, another is refused as busy, so an older request's
    model never replaces a newer one's; the first one's model is served."""
    results: list[MotionModel] = []
    first = threading.Thread(
        target=lambda: results.append(current.fit(FitRequest(files=[DEMOS]))),
    )
    first.start()
    while not current.fitting and first.is_alive():
        time.sleep(0.001)
    assert current.fitting, "the first fit ended before the second was asked"
    with pytest.raises(ServiceBusyError) as busy:
        current.fit(FitRequest(files=[DEMOS], bins=10))
    assert "a fit is running (one at a time)" in busy.value.message
    assert "requests are already waiting" not in busy.value.message
    first.join()
    assert current.get(NoArguments()) == results[0]
    assert not current.fitting
