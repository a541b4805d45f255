"""The stop signals held for a few steps (``shared.held_signals``) are all
put back, whatever signal comes as they are swapped."""

from __future__ import annotations

import signal
from types import FrameType
from typing import Any

import pytest

from shared.held_signals import held_signals


class Stopped(KeyboardInterrupt):
    """What the test's own SIGTERM handler raises."""


def _stop(signum: int, frame: FrameType | None) -> None:
    raise Stopped


@pytest.fixture
def handlers() -> Any:
    """SIGTERM raising :class:`Stopped`; Ctrl-C's and SIGHUP's as Python has them."""
    before = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGHUP)}
    signal.signal(signal.SIGTERM, _stop)
    yield
    for signum, handler in before.items():
        signal.signal(signum, handler)
    signal.signal(signal.SIGINT, signal.default_int_handler)


def _signal_after(
    monkeypatch: pytest.MonkeyPatch, setting: Any, sent: signal.Signals
) -> None:
    """A real ``sent`` to this process right after a handler is set to ``setting``
    (the handler of ``signal.SIGINT`` when ``setting`` is ``"note"``)."""
    set_handler = signal.signal

    def then_signal(signum: int, handler: Any) -> Any:
        was = set_handler(signum, handler)
        wanted = (
            signum == signal.SIGINT and handler is not signal.default_int_handler
            if setting == "note"
            else handler is setting
        )
        if wanted:
            monkeypatch.undo()
            signal.raise_signal(sent)  # its handler runs here
        return was

    monkeypatch.setattr(signal, "signal", then_signal)


def test_a_ctrl_c_just_after_its_handler_is_back_leaves_none_noting(
    handlers: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C right after its own handler was put back raised there, in the
    middle of putting them back: SIGTERM and SIGHUP stayed noted for good,
    a later SIGTERM to this process taken by nobody."""
    _signal_after(monkeypatch, signal.default_int_handler, signal.SIGINT)
    with pytest.raises(KeyboardInterrupt), held_signals():
        pass
    assert signal.getsignal(signal.SIGTERM) is _stop
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_DFL


def test_a_sigterm_as_the_handlers_are_set_leaves_none_noting(
    handlers: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """SIGTERM right after Ctrl-C's handler was set to note: its own handler
    raised before the block, and Ctrl-C was noted for good (never raised
    again in this process)."""
    _signal_after(monkeypatch, "note", signal.SIGTERM)
    ran = False
    with pytest.raises(Stopped), held_signals():
        ran = True
    assert not ran
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert signal.getsignal(signal.SIGTERM) is _stop


def test_a_signal_noted_in_the_block_comes_after_it(handlers: None) -> None:
    """The steps all run; the SIGTERM that came meanwhile is raised after them."""
    steps = []
    with pytest.raises(Stopped), held_signals():
        steps.append(1)
        signal.raise_signal(signal.SIGTERM)
        steps.append(2)
    assert steps == [1, 2]
    assert signal.getsignal(signal.SIGTERM) is _stop
