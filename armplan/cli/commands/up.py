"""``armplan up``: start the router and every service; stop them all on a signal."""

from __future__ import annotations

import argparse
import signal
import sys
import threading

from armplan.launch import SERVICES, Launcher
from shared.bus import Bus, BusConfig, load_config

ORDER = 80
HELP = "start the Zenoh router and every service; Ctrl-C or SIGTERM stops them all"
#: Pause between checks on the children while running [s].
POLL = 0.2


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``up``."""
    parser = commands.add_parser("up", help=HELP, description=HELP)
    parser.add_argument(
        "--config", metavar="FILE", help="armplan Zenoh config (default: the repo's)"
    )
    parser.add_argument(
        "--listen",
        action="append",
        metavar="ENDPOINT",
        help="router endpoint (default tcp/127.0.0.1:7447, from the config)",
    )
    parser.add_argument(
        "--only",
        nargs="+",
        metavar="SERVICE",
        choices=[s.name for s in SERVICES],
        help="start only these services (default: all)",
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Start everything, print where it listens, run until SIGTERM/SIGINT."""
    config = load_config(args.config, tuple(args.listen or ()))
    stop = _stop_on_signals()
    launcher = Launcher(config, args.only, stop=stop)
    with launcher:  # starts; stops everything on the way out
        _print_started(launcher, config)
        _watch(launcher, stop)
    _say("armplan up: stopped every process")
    return 0


def _stop_on_signals() -> threading.Event:
    stop = threading.Event()

    def request_stop(signum: int, frame: object) -> None:
        stop.set()

    signal.signal(signal.SIGTERM, request_stop)
    signal.signal(signal.SIGINT, request_stop)
    return stop


def _print_started(launcher: Launcher, config: BusConfig) -> None:
    assert launcher.router is not None
    _say(
        f"router   pid {launcher.router.pid:<7d} listening on "
        f"{', '.join(config.endpoints)} (namespace {config.namespace}, "
        f"config {config.source})"
    )
    for spec in launcher.specs:
        keys = ", ".join(r.key(config.namespace) for r in spec.routes)
        pid = launcher.services[spec.name].pid
        _say(f"{spec.name:<8} pid {pid:<7d} {keys}")
    with Bus.connect(config) as bus:
        alive = ", ".join(bus.alive())
    _say(f"armplan up: ready, alive: {alive}; Ctrl-C or SIGTERM stops them all")


def _watch(launcher: Launcher, stop: threading.Event) -> None:
    """Wait for a stop request; report children that exit meanwhile."""
    reported: set[int] = set()
    while not stop.wait(POLL):
        for child in launcher.exited():
            if child.pid not in reported:
                reported.add(child.pid)
                sys.stderr.write(
                    f"armplan up: {child.name} (pid {child.pid}) exited with code "
                    f"{child.exit_code()}\n"
                )


def _say(line: str) -> None:
    sys.stdout.write(line + "\n")
    sys.stdout.flush()
