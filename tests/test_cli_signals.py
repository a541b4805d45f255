"""A signal is reported as itself, whatever exception it surfaced as.

SIGTERM's handler raises :class:`Terminated` in whatever code runs when it
lands. Inside a pydantic serializer, pydantic-core reports it as a
``PydanticSerializationError``; ``armplan demo`` then exited 1 with that
error instead of 143 ("terminated"). Here the signal is sent from inside a
real serializer, so it lands there every time.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import time
import weakref
from collections.abc import Callable, Iterator
from typing import Any

import pydantic
import pytest
from pydantic_core import PydanticSerializationError

from armplan.cli.main import run_command
from armplan.cli.termination import forget_signals, terminate_on_sigterm
from shared.errors import InvalidInputError

#: The signals the CLI's handlers take over.
STOPS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
#: Each signal, the exit code and what the CLI says of it.
STOPPED = [
    (signal.SIGTERM, 143, "armplan: terminated\n"),
    (signal.SIGINT, 130, "armplan: interrupted\n"),
    (signal.SIGHUP, 129, "armplan: hung up\n"),
]


@pytest.fixture
def handlers() -> Iterator[None]:
    """The CLI's signal handlers, then pytest's again."""
    held = {s: signal.getsignal(s) for s in STOPS}
    forget_signals()
    terminate_on_sigterm()
    try:
        yield
    finally:
        for signum, handler in held.items():
            signal.signal(signum, handler)
        forget_signals()


class Signalling(pydantic.BaseModel):
    """A message whose serializer receives ``signum`` while it runs."""

    signum: int

    @pydantic.model_serializer(mode="wrap")
    def _serialize(self, handler: Any) -> Any:
        os.kill(os.getpid(), self.signum)
        return handler(self)


def _serializing(signum: signal.Signals) -> Any:
    def run(args: argparse.Namespace) -> int:
        Signalling(signum=signum).model_dump_json()
        return 0

    return run


@pytest.mark.parametrize(("signum", "code", "said"), STOPPED)
def test_a_signal_inside_a_serializer_is_reported_as_the_signal(
    handlers: None,
    capsys: pytest.CaptureFixture[str],
    signum: signal.Signals,
    code: int,
    said: str,
) -> None:
    """The exception comes out as pydantic's, yet the exit code is the signal's."""
    with pytest.raises(PydanticSerializationError):
        _serializing(signum)(argparse.Namespace())  # what used to reach main
    forget_signals()
    assert run_command(_serializing(signum), argparse.Namespace()) == code
    assert capsys.readouterr().err == said


def test_an_armplan_error_after_sigterm_is_reported_as_terminated(
    handlers: None, capsys: pytest.CaptureFixture[str]
) -> None:
    """An error raised while SIGTERM unwinds the command (a stop that fails
    because the bus closed) does not hide that SIGTERM ended it."""

    def run(args: argparse.Namespace) -> int:
        try:
            os.kill(os.getpid(), signal.SIGTERM)
        finally:
            raise InvalidInputError("the bus closed meanwhile")

    assert run_command(run, argparse.Namespace(json=False)) == 143
    assert capsys.readouterr().err == "armplan: terminated\n"


def test_without_a_signal_errors_are_reported_as_before(
    handlers: None, capsys: pytest.CaptureFixture[str]
) -> None:
    """No signal: an armplan error exits 1 naming what was wrong; another
    error is not swallowed."""

    def bad_input(args: argparse.Namespace) -> int:
        raise InvalidInputError("the task file names no target")

    assert run_command(bad_input, argparse.Namespace(json=False)) == 1
    assert "the task file names no target" in capsys.readouterr().err

    def serializing(args: argparse.Namespace) -> int:
        raise PydanticSerializationError("not a signal")

    with pytest.raises(PydanticSerializationError):
        run_command(serializing, argparse.Namespace(json=False))


def test_a_signal_ignored_at_start_stays_ignored() -> None:
    """``armplan demo &`` in a script starts with SIGINT ignored: the
    handlers used to take it over, and the script's Ctrl-C ended the demo;
    ``nohup armplan demo`` starts with SIGHUP ignored."""
    held = {s: signal.getsignal(s) for s in STOPS}
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
        terminate_on_sigterm()
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGTERM) not in (signal.SIG_IGN, signal.SIG_DFL)
    finally:
        for signum, handler in held.items():
            signal.signal(signum, handler)
        forget_signals()


class _Finalized:
    """An object that receives ``signum`` as it is finalized."""

    def __init__(self, signum: signal.Signals) -> None:
        self.signum = signum

    def __del__(self) -> None:
        os.kill(os.getpid(), self.signum)


def _dropping(how: str, signum: signal.Signals) -> Callable[[], None]:
    """Drop an object whose finalizer (``__del__``, or a weakref callback as
    importlib's module locks have) receives ``signum``."""

    def by_del() -> None:
        _Finalized(signum)

    def by_weakref() -> None:
        target = argparse.Namespace()
        kept = weakref.ref(target, lambda _: os.kill(os.getpid(), signum))
        del target
        assert kept() is None

    return {"__del__": by_del, "weakref": by_weakref}[how]


@pytest.mark.parametrize("how", ["__del__", "weakref"])
@pytest.mark.parametrize(("signum", "code", "said"), STOPPED)
def test_a_signal_landing_in_a_finalizer_still_stops_the_command(
    capsys: pytest.CaptureFixture[str],
    how: str,
    signum: signal.Signals,
    code: int,
    said: str,
) -> None:
    """Python swallows an exception raised in a finalizer ("Exception ignored
    in ..."): a SIGHUP that landed in importlib's weakref callback let an
    experiment run to its end. The command stops at once all the same, and
    the test runner's unraisable hook is put back."""
    hook = sys.unraisablehook
    went_on: list[int] = []

    def run(args: argparse.Namespace) -> int:
        _dropping(how, signum)()
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            time.sleep(0.01)
        went_on.append(1)
        return 0

    assert run_command(run, argparse.Namespace(json=False)) == code
    assert not went_on
    assert capsys.readouterr().err == said
    assert sys.unraisablehook is hook
    forget_signals()


def test_an_exception_swallowed_that_is_no_stop_goes_to_the_hook_before() -> None:
    """Another exception raised in a finalizer is still reported as Python
    reports it (by the hook that was there), and the command goes on."""
    seen: list[BaseException | None] = []
    hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: seen.append(unraisable.exc_value)

    class Failing:
        def __del__(self) -> None:
            raise ValueError("a finalizer's own error")

    def run(args: argparse.Namespace) -> int:
        Failing()
        return 0

    try:
        assert run_command(run, argparse.Namespace(json=False)) == 0
    finally:
        sys.unraisablehook = hook
    assert [type(error) for error in seen] == [ValueError]
