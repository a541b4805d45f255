"""Signals to stop requests without a lock in the handler (shared.stop_signals)."""

from __future__ import annotations

import gc
import signal
import subprocess
import sys
import textwrap
import threading
from collections.abc import Iterator

import pytest

from shared import stop_signals
from shared.stop_signals import stop_on_signals

#: A signal no armplan code uses, so the tests can take it over.
SIGNAL = signal.SIGUSR1


@pytest.fixture
def own_signal() -> Iterator[int]:
    """SIGUSR1, its previous handler put back afterwards."""
    previous = signal.getsignal(SIGNAL)
    yield SIGNAL
    signal.signal(SIGNAL, previous)


def test_a_signal_sets_the_stop_request(own_signal: int) -> None:
    """The event is not set before the signal and is set soon after it."""
    stop = stop_on_signals([own_signal])
    assert not stop.is_set()
    signal.raise_signal(own_signal)
    assert stop.wait(5.0)


def test_the_stop_request_knows_the_first_signal(own_signal: int) -> None:
    """`armplan up` stopped while starting says which signal stopped it: the
    request keeps the first signal that set it, a later one does not
    replace it."""
    second = signal.SIGUSR2
    previous = signal.getsignal(second)
    try:
        stop = stop_on_signals([own_signal, second])
        assert stop.signal is None
        signal.raise_signal(own_signal)
        assert stop.wait(5.0) and stop.signal == own_signal
        signal.raise_signal(second)
        again = stop_on_signals([own_signal, second])
        signal.raise_signal(second)
        assert again.wait(5.0) and again.signal == second
        assert stop.signal == own_signal
    finally:
        signal.signal(second, previous)


@pytest.mark.timeout(30)
def test_a_signal_while_the_event_is_held_does_not_hang(own_signal: int) -> None:
    """The handler runs while this thread holds the event's own lock, as it
    does for a moment in every pass of event.wait(timeout): it returns, and
    the event is set once the lock is free (a handler calling Event.set here
    would wait forever for its own thread)."""
    stop = stop_on_signals([own_signal])
    with stop._cond:  # what Event.wait holds around its check
        signal.raise_signal(own_signal)  # the handler runs now, in this thread
        assert not stop.is_set()  # set() needs the lock held here
    assert stop.wait(5.0)


def test_every_stop_request_hears_the_signal(own_signal: int) -> None:
    """Two requests made in one process are both set by one signal."""
    first, second = stop_on_signals([own_signal]), stop_on_signals([own_signal])
    signal.raise_signal(own_signal)
    assert first.wait(5.0) and second.wait(5.0)


def test_a_dropped_stop_request_is_forgotten(own_signal: int) -> None:
    """Asking again and again does not pile up events nobody holds."""
    kept = stop_on_signals([own_signal])
    for _ in range(100):
        stop_on_signals([own_signal])
    gc.collect()
    relay = stop_signals._the_relay()
    assert kept in relay.events and len(relay.events) < 10


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_a_waiting_process_stops_on_sigterm_and_sighup(signum: int) -> None:
    """A real process waiting in the bus processes' loop exits 0 on SIGTERM,
    and on SIGHUP (its terminal closed), which killed it before."""
    script = textwrap.dedent(
        """
        from shared.bus.process import wait_for
        from shared.stop_signals import stop_on_signals
        stop = stop_on_signals()
        print("waiting", flush=True)
        wait_for(stop)
        print("stopped", flush=True)
        """
    )
    with subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, text=True
    ) as child:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "waiting"
        child.send_signal(signum)
        assert child.wait(10.0) == 0
        assert child.stdout.read().strip() == "stopped"


@pytest.mark.parametrize("name", ["SIGHUP", "SIGINT"])
def test_a_signal_ignored_at_start_stays_ignored(name: str) -> None:
    """``nohup`` (SIGHUP), or a script's ``cmd &`` (SIGINT): a stop signal
    ignored at start is not taken over (a script's Ctrl-C stopped the
    ``armplan record &`` it ran); SIGTERM still stops the process."""
    script = textwrap.dedent(
        f"""
        import signal
        from shared.stop_signals import stop_on_signals
        signal.signal(signal.{name}, signal.SIG_IGN)  # as the shell starts it
        stop = stop_on_signals()
        print(signal.getsignal(signal.{name}) is signal.SIG_IGN, flush=True)
        signal.raise_signal(signal.{name})
        print(stop.wait(0.5), flush=True)
        signal.raise_signal(signal.SIGTERM)
        print(stop.wait(10.0), flush=True)
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "False", "True"]


def test_a_signal_held_before_is_taken(own_signal: int) -> None:
    """A stop signal blocked and pending when the request is made (``armplan
    sim`` holds Ctrl-C across its exec) sets it at once, and is unblocked."""
    signal.pthread_sigmask(signal.SIG_BLOCK, [own_signal])
    try:
        signal.pthread_kill(threading.main_thread().ident or 0, own_signal)
        stop = stop_on_signals([own_signal])
        assert stop.is_set() and stop.signal == own_signal
        assert own_signal not in signal.pthread_sigmask(signal.SIG_BLOCK, [])
    finally:
        signal.sigtimedwait([own_signal], 0)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, [own_signal])


def test_an_ignored_signal_held_before_is_unblocked() -> None:
    """``armplan sim &`` in a script: Ctrl-C ignored, and held by ``armplan
    sim`` across its exec. It stays ignored (no stop), but is no longer
    blocked: it was, for the sim's whole life (and any child's)."""
    script = textwrap.dedent(
        """
        import signal
        from shared.stop_signals import stop_on_signals
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # as the shell starts it
        signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGINT])  # held
        signal.raise_signal(signal.SIGINT)  # a Ctrl-C while it was held
        stop = stop_on_signals()
        print(signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, []))
        print(signal.SIGINT in signal.sigpending(), stop.is_set(), flush=True)
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "False", "False"]


def test_held_signals_pending_together_are_taken_ctrl_c_first() -> None:
    """SIGTERM and Ctrl-C both held across ``armplan sim``'s exec: the stop
    request names Ctrl-C, as ``armplan``'s own hold does
    (``armplan.cli.held_interrupt``), whatever order they came in."""
    script = textwrap.dedent(
        """
        import signal
        from shared.stop_signals import stop_on_signals
        held = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]
        signal.pthread_sigmask(signal.SIG_BLOCK, held)
        signal.raise_signal(signal.SIGTERM)
        signal.raise_signal(signal.SIGINT)
        stop = stop_on_signals()
        print(stop.signal.name, flush=True)
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["SIGINT"]
