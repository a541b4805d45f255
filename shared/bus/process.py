"""What every armplan bus process does at start: logging, signals, arguments."""

from __future__ import annotations

import argparse
import gc
import logging
import sys
import threading

from shared.bus.lifeline import watch_parent
from shared.stop_signals import stop_on_signals

#: Period at which a waiting process checks for its stop request [s].
POLL = 0.2


def start_process(level: str = "INFO") -> threading.Event:
    """Log to stderr, stop on SIGTERM/SIGINT/SIGHUP, die with the launcher.

    Args:
        level: Logging level name, e.g. ``"INFO"``.

    Returns:
        The event set when the process is asked to stop.
    """
    logging.basicConfig(
        level=level.upper(),
        stream=sys.stderr,
        format="%(asctime)s %(name)s[%(process)d] %(levelname)s %(message)s",
    )
    stop = stop_on_signals()
    watch_parent()
    return stop


def wait_for(stop: threading.Event) -> None:
    """Block until ``stop`` is set (signals stay responsive).

    Called once the process has set up: what it made until then is frozen
    first (:func:`freeze_set_up`; the services and the bridge have frozen
    already, before their liveliness token, and this finds little new).
    """
    freeze_set_up()
    while not stop.wait(POLL):
        pass


def freeze_set_up() -> None:
    """Keep what the process made so far out of the garbage collector's scans.

    A service's imports and set-up (numpy, pinocchio, pydantic's schemas,
    the motion model, the Zenoh session) leave about 90 000 objects that
    live as long as the process. CPython's first full collection scans
    them all: in a process planning one-second reaches in a loop, it came
    at about the 25th plan and took 64-80 ms, a hitch in a 20 ms plan.
    Frozen (``gc.freeze``), they are never scanned again; what the process
    makes later still is, and cycles among it are still collected.
    (Through the services, ``armplan bench``'s p99 did not change
    measurably: 57-59 ms without, 53-61 ms with, two runs of 200 plans each
    on a 2-CPU machine; there the hitch hides in the noise.)
    """
    gc.collect()
    gc.freeze()


def add_common_arguments(parser: argparse.ArgumentParser) -> None:
    """``--config FILE`` and ``--log-level``, shared by the router and services."""
    parser.add_argument(
        "--config", metavar="FILE", help="the armplan Zenoh config (JSON5)"
    )
    parser.add_argument(
        "--log-level", default="INFO", help="DEBUG, INFO, WARNING or ERROR"
    )
