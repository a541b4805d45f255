"""A remote fit whose ``armplan fit --remote`` was interrupted or killed.

A real router, fit service process and client process on loopback. The
client asks for a fit of 160 reaches (seconds) with a 120 s ``--timeout``;
once the service is fitting it is paused (SIGSTOP), the client is
interrupted (Ctrl-C) or killed, and the service resumed once the client's
caller token has gone. The fit used to go on and replace the served model
(published on ``fit/model/update``), minutes after the lab had taken the
fit as cancelled; now the service abandons it and serves the model before.
"""

from __future__ import annotations

import pathlib
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator

import pytest
import zenoh

from armplan.launch import Launcher
from armplan.launch.child import Child
from shared.bus import Bus, NoArguments
from shared.bus.keys import caller_pattern
from shared.bus.routes import FIT, FIT_MODEL, MODEL_TOPIC
from shared.errors import DemoFileError, RequestTimeoutError, ServiceBusyError
from shared.messages import FitRequest, MotionModel, parse
from tests.fit_stack import BIG, SMALL, fit_stack

#: Longest wait for any one thing the test waits for [s].
WAIT = 60.0


@pytest.fixture()
def stack(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[tuple[Launcher, pathlib.Path]]:
    """Router and fit service reading tmp_path; the service's log file."""
    with fit_stack(tmp_path, monkeypatch) as launched:
        yield launched


class Callers:
    """The caller tokens seen come and go (``<ns>/caller/<session id>``)."""

    def __init__(self, bus: Bus) -> None:
        self.came: list[str] = []
        self.went: list[str] = []
        self.changed = threading.Condition()
        self._subscriber = bus.session.liveliness().declare_subscriber(
            caller_pattern(bus.config.namespace), self._on_sample
        )

    def _on_sample(self, sample: zenoh.Sample) -> None:
        with self.changed:
            seen = self.came if sample.kind == zenoh.SampleKind.PUT else self.went
            seen.append(str(sample.key_expr))
            self.changed.notify_all()

    def close(self) -> None:
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]


def fitting(bus: Bus) -> bool:
    """Whether the fit service runs a fit now (a probe is refused busy).

    The probe names a missing file: refused without any fit when none runs.
    """
    try:
        bus.call(FIT, FitRequest(files=["missing.mcap"]), timeout=WAIT)
    except ServiceBusyError:
        return True
    except DemoFileError:
        return False
    raise AssertionError("a fit of a missing file was not refused")


def wait_for(condition: str, check: Callable[[], object]) -> None:
    """Poll ``check()`` every 0.1 s until true, at most ``WAIT`` seconds."""
    deadline = time.monotonic() + WAIT
    while not check():
        assert time.monotonic() < deadline, f"never {condition}"
        time.sleep(0.1)


def pause_when_fitting(launched: Launcher, bus: Bus, callers: Callers) -> Child:
    """The fit service, paused (SIGSTOP) once its caller's fit runs.

    The caller is seen connect first and given 0.5 s for its query to go
    out: a probe sent before it would take the fit's turn.
    """
    wait_for("saw the caller connect", lambda: callers.came)
    time.sleep(0.5)
    wait_for("saw the caller's fit run", lambda: fitting(bus))
    fit = launched.services["fit"]
    fit.signal(signal.SIGSTOP)
    return fit


@pytest.mark.parametrize(
    ("stop", "code"),
    [(signal.SIGINT, 130), (signal.SIGKILL, -signal.SIGKILL)],
    ids=["ctrl-c", "killed"],
)
def test_a_fit_whose_caller_was_interrupted_is_abandoned(
    stack: tuple[Launcher, pathlib.Path], stop: signal.Signals, code: int
) -> None:
    """Nothing is published for the abandoned fit, the model before is still
    served, the service's log says why, and the next fit is served as usual."""
    launched, log = stack
    updates: list[MotionModel] = []
    with Bus.connect(launched.config) as bus:
        before = bus.call(FIT_MODEL, NoArguments())
        callers = Callers(bus)
        subscriber = bus.session.declare_subscriber(
            bus.key(MODEL_TOPIC),
            lambda s: updates.append(parse(MotionModel, s.payload.to_bytes())),
        )
        try:
            time.sleep(0.5)  # the router learns of the subscribers
            where = ["--connect", launched.config.endpoint, "--timeout", "120"]
            client = subprocess.Popen(
                [sys.executable, "-m", "armplan", "fit", BIG, "--remote", *where],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
            )
            fit = pause_when_fitting(launched, bus, callers)
            try:
                client.send_signal(stop)
                _, err = client.communicate(timeout=WAIT)
                assert client.returncode == code, err
                token = callers.came[0]
                with callers.changed:
                    went = callers.changed.wait_for(lambda: token in callers.went, WAIT)
                assert went, "the client's caller token never went"
            finally:
                fit.signal(signal.SIGCONT)
            wait_for("saw the fit end", lambda: not fitting(bus))
            assert bus.call(FIT_MODEL, NoArguments()) == before
            fitted = bus.call(FIT, FitRequest(files=[SMALL]), timeout=WAIT)
            wait_for("saw the next fit published", lambda: updates)
            assert bus.call(FIT_MODEL, NoArguments()) == fitted != before
        finally:
            subscriber.undeclare()  # type: ignore[no-untyped-call]
            callers.close()
    assert [m.sources for m in updates] == [[SMALL]]
    if stop == signal.SIGINT:
        assert "the fit service abandons this fit" in err
    text = log.read_text()
    assert f"fit on {BIG} stopped after" in text, text
    assert "its caller's session ended (interrupted or killed)" in text, text


def test_a_fit_whose_caller_timed_out_then_left_says_it_stopped_waiting(
    stack: tuple[Launcher, pathlib.Path],
) -> None:
    """A caller that stopped waiting (its ``--timeout`` passed) and then
    closed its session, as ``armplan fit --remote`` does when it exits 1 on
    request_timeout, was logged as "interrupted or killed": the session's
    end was said before the deadline that passed first. The service is
    paused until both have happened, so its next check sees the two."""
    launched, log = stack
    with Bus.connect(launched.config) as bus:
        callers = Callers(bus)
        timed_out: list[BaseException] = []

        def ask() -> None:
            with Bus.connect(launched.config) as caller:
                try:
                    caller.call(FIT, FitRequest(files=[BIG]), timeout=3.0)
                except RequestTimeoutError as error:
                    timed_out.append(error)

        asking = threading.Thread(target=ask)
        try:
            asking.start()
            fit = pause_when_fitting(launched, bus, callers)
            try:
                asking.join(WAIT)
                assert timed_out, "the caller did not time out"
                token = callers.came[0]
                with callers.changed:
                    went = callers.changed.wait_for(lambda: token in callers.went, WAIT)
                assert went, "the caller's token never went"
            finally:
                fit.signal(signal.SIGCONT)
            wait_for("saw the fit end", lambda: not fitting(bus))
        finally:
            asking.join(WAIT)
            callers.close()
    text = log.read_text()
    assert f"fit on {BIG} stopped after" in text, text
    assert "its caller stopped waiting (3.0 s); no model installed" in text, text
    assert "interrupted or killed" not in text, text
