"""``python -m bridge.sim --listen tcp://127.0.0.1:9559 [--log FILE]``.

Importing ``bridge`` first loads libqi before pinocchio (see shared/libqi.py).
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
from collections.abc import Sequence

from bridge.address import check_listen_url
from bridge.sim.cycle import PERIOD, check_period
from bridge.sim.log import check_log_file
from bridge.sim.server import DEFAULT_LISTEN, serve
from shared.command_line import ArgumentParser
from shared.errors import ArmplanError, InvalidInputError
from shared.sim_options import add_sim_options, check_sim_options
from shared.stop_signals import StartInterrupted, stop_on_signals

#: The exit code after Ctrl-C (128 + SIGINT), as ``armplan``'s.
INTERRUPTED_CODE = 128 + signal.SIGINT
#: What a stop signal held while it started is said as, and its exit code,
#: as ``armplan``'s (``armplan sim`` holds them across its ``exec``).
STOPPED = {
    signal.SIGINT: ("interrupted", INTERRUPTED_CODE),
    signal.SIGTERM: ("terminated", 128 + signal.SIGTERM),
    signal.SIGHUP: ("hung up", 128 + signal.SIGHUP),
}


def parser() -> argparse.ArgumentParser:
    """The command line of the simulated NAO."""
    p = ArgumentParser(
        prog="python -m bridge.sim",
        description="A simulated NAO serving ALMotion over NAOqi (libqi).",
    )
    add_arguments(p)
    return p


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``--listen``, ``--log``, ``--period``, ``--killed-calls-return`` and more."""
    p.add_argument(
        "--listen",
        default=DEFAULT_LISTEN,
        help=f"NAOqi address to serve at (default {DEFAULT_LISTEN}; port 0: any)",
    )
    p.add_argument("--log", default=None, help="JSON-lines log of commands and states")
    p.add_argument(
        "--period", type=float, default=PERIOD, help="control cycle [s] (default 0.02)"
    )
    add_sim_options(p)
    p.add_argument(
        "--stop-on-stdin-eof",
        action="store_true",
        help="stop when standard input closes (its parent process ended)",
    )
    # The command a person typed, for error messages (``armplan sim`` execs this).
    p.add_argument("--prog", default=None, help=argparse.SUPPRESS)


def _watch_stdin(stop: threading.Event) -> None:
    """Set ``stop`` when standard input reaches its end."""
    for _ in sys.stdin:
        pass
    stop.set()


def run(
    listen: str,
    log: str | None,
    period: float,
    stop_on_eof: bool = False,
    killed_returns: bool = False,
    limp_sag: float = 0.0,
    grip: float | None = None,
) -> int:
    """Serve until SIGINT or SIGTERM (or stdin's end); returns the exit code.

    Raises:
        StartInterrupted: a Ctrl-C held while this process started (``armplan
            sim`` holds it across its ``exec``); nothing was served.
    """
    stop = stop_on_signals()
    if stop.is_set():
        raise StartInterrupted(stop.signal)
    if stop_on_eof:
        threading.Thread(target=_watch_stdin, args=(stop,), daemon=True).start()
    serve(listen, log, period, stop, killed_returns, limp_sag, grip)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit code.

    A malformed address or period, or a log file that cannot be written, is
    a usage error (exit 2); an address it cannot listen at exits 1 with the
    reason on one line. Ctrl-C held while it started exits 130, saying
    ``interrupted`` (SIGTERM 143, ``terminated``; SIGHUP 129, ``hung up``).
    """
    p = parser()
    args = p.parse_args(argv)
    p.prog = args.prog or p.prog
    try:
        check_listen_url(args.listen)
        check_period(args.period)
        check_sim_options(args)
        if args.log is not None:
            check_log_file(args.log)
    except InvalidInputError as error:
        p.error(error.message)
    try:
        return run(
            args.listen,
            args.log,
            args.period,
            args.stop_on_stdin_eof,
            args.killed_calls_return,
            args.limp_sag,
            args.grip,
        )
    except ArmplanError as error:  # e.g. the address is in use
        sys.stderr.write(f"{p.prog}: error: {error.message}\n")
        return 1
    except StartInterrupted as stop:
        said, code = STOPPED[stop.signal or signal.SIGINT]
        sys.stderr.write(f"{p.prog}: {said}\n")
        return code


def exit_now(code: int) -> None:
    """End the process with ``code``, skipping the interpreter's teardown.

    Everything is closed by then; libqi's threads can abort (SIGABRT) while
    Python finalises, which turned a clean stop into exit code -6 (seen once
    in CI).
    """
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    exit_now(main())
