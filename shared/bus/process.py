"""What every armplan bus process does at start: logging, signals, arguments."""

from __future__ import annotations

import argparse
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
    """Block until ``stop`` is set (signals stay responsive)."""
    while not stop.wait(POLL):
        pass


def add_common_arguments(parser: argparse.ArgumentParser) -> None:
    """``--config FILE`` and ``--log-level``, shared by the router and services."""
    parser.add_argument(
        "--config", metavar="FILE", help="the armplan Zenoh config (JSON5)"
    )
    parser.add_argument(
        "--log-level", default="INFO", help="DEBUG, INFO, WARNING or ERROR"
    )
