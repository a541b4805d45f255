"""Ctrl-C held while the commands load (armplan.cli.held_interrupt)."""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator

import pytest

from armplan.cli.held_interrupt import held_interrupt


def _ctrl_c() -> None:
    """SIGINT to this (main) thread only: no other thread can take it."""
    signal.pthread_kill(threading.main_thread().ident or 0, signal.SIGINT)


@pytest.fixture
def unblocked() -> Iterator[None]:
    """SIGINT neither blocked nor pending here afterwards, whatever happened."""
    yield
    signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGINT])
    signal.sigtimedwait([signal.SIGINT], 0)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])


def test_a_ctrl_c_inside_is_taken_not_raised(unblocked: None) -> None:
    """No KeyboardInterrupt inside or after the block; ``came`` says it came."""
    with held_interrupt() as held:
        _ctrl_c()
        assert not held.came
    assert held.came
    assert signal.SIGINT not in signal.pthread_sigmask(signal.SIG_BLOCK, [])


def test_no_ctrl_c_leaves_nothing_held(unblocked: None) -> None:
    """Without a Ctrl-C, ``came`` is false and SIGINT is unblocked again."""
    with held_interrupt() as held:
        pass
    assert not held.came
    assert signal.SIGINT not in signal.pthread_sigmask(signal.SIG_BLOCK, [])


def test_a_ctrl_c_blocked_before_stays_blocked(unblocked: None) -> None:
    """SIGINT blocked by whoever started the process is left blocked, pending."""
    signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGINT])
    with held_interrupt() as held:
        _ctrl_c()
    assert not held.came
    assert signal.SIGINT in signal.sigpending()


def test_an_ignored_ctrl_c_is_not_taken(unblocked: None) -> None:
    """``armplan record &`` in a script ignores SIGINT: the script's Ctrl-C
    while it loads is not for it. Held, the ignored signal stayed pending
    (blocked signals are kept, ignored or not) and came out as a Ctrl-C."""
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with held_interrupt() as held:
            _ctrl_c()
        assert not held.came
        assert signal.SIGINT not in signal.sigpending()
        assert signal.SIGINT not in signal.pthread_sigmask(signal.SIG_BLOCK, [])
    finally:
        signal.signal(signal.SIGINT, before)


def test_a_sigterm_inside_is_taken_and_named(unblocked: None) -> None:
    """SIGTERM (and SIGHUP) while held: taken, not acted on, and named."""
    for signum in (signal.SIGTERM, signal.SIGHUP):
        with held_interrupt() as held:
            signal.pthread_kill(threading.main_thread().ident or 0, signum)
            assert held.signal is None
        assert held.signal == signum
        assert signum not in signal.pthread_sigmask(signal.SIG_BLOCK, [])


def test_a_ctrl_c_blocked_before_leaves_sigterm_unblocked_after(
    unblocked: None,
) -> None:
    """With SIGINT blocked by whoever started the process, the hold still
    ends for SIGTERM and SIGHUP: left blocked, they would never stop it."""
    signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGINT])
    with held_interrupt():
        pass
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    assert signal.SIGINT in mask
    assert signal.SIGTERM not in mask and signal.SIGHUP not in mask


def test_with_ctrl_c_ignored_sigterm_is_still_held(unblocked: None) -> None:
    """``cmd &`` in a script ignores Ctrl-C; a SIGTERM while the commands
    load is still held and named (it killed the command with no word)."""
    delivered: list[int] = []  # not held, it would have come here, not killed
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    term = signal.signal(signal.SIGTERM, lambda signum, frame: delivered.append(signum))
    try:
        with held_interrupt() as held:
            signal.pthread_kill(threading.main_thread().ident or 0, signal.SIGTERM)
        assert held.signal == signal.SIGTERM
        assert delivered == []
        assert signal.SIGTERM not in signal.pthread_sigmask(signal.SIG_BLOCK, [])
    finally:
        signal.signal(signal.SIGINT, before)
        signal.signal(signal.SIGTERM, term)
