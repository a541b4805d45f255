"""A fit whose caller stopped waiting stops, and does not block the retry.

A real router and fit service process on loopback. The fit of 160 reaches
takes seconds (reading them, most of a second); its caller waits 0.3 s, so
the retry usually finds it still reading, past its deadline. The fit used
to run to its end (11 s after a 4 s timeout, on a larger set), refusing the
caller's retry as busy with "its model is served when it ends", then
dropped its model.
"""

from __future__ import annotations

import pathlib
import time
from collections.abc import Iterator

import pytest

from armplan.launch import Launcher
from shared.bus import Bus, NoArguments
from shared.bus.routes import FIT, FIT_MODEL
from shared.errors import RequestTimeoutError, ServiceBusyError
from shared.messages import FitRequest
from tests.fit_stack import BIG, SMALL, fit_stack


@pytest.fixture()
def stack(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[tuple[Launcher, pathlib.Path]]:
    """Router and fit service reading tmp_path; the service's log file."""
    with fit_stack(tmp_path, monkeypatch) as launched:
        yield launched


def test_a_fit_whose_caller_stopped_waiting_stops_and_frees_the_retry(
    stack: tuple[Launcher, pathlib.Path],
) -> None:
    """The caller is told request_timeout; every retry refused meanwhile says
    the running fit's model will not be served; the retry is then fitted and
    served; the service's log says the first fit stopped early."""
    launched, log = stack
    with Bus.connect(launched.config) as bus:
        before = bus.call(FIT_MODEL, NoArguments())
        with pytest.raises(RequestTimeoutError):
            bus.call(FIT, FitRequest(files=[BIG]), timeout=0.3)
        refusals: list[str] = []
        while True:
            try:
                fitted = bus.call(FIT, FitRequest(files=[SMALL]), timeout=60.0)
                break
            except ServiceBusyError as busy:
                refusals.append(busy.message)
                time.sleep(0.05)
        assert all("will not be served" in why for why in refusals), refusals
        served = bus.call(FIT_MODEL, NoArguments())
    assert served == fitted != before
    assert fitted.sources == [SMALL]
    text = log.read_text()
    assert f"fit on {BIG} stopped after" in text, text
    assert f"fitted on {BIG} after its caller stopped waiting" not in text, text
