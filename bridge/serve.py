"""``python -m bridge.serve``: the robot bridge as a Zenoh service process.

Usage: ``python -m bridge.serve [--robot tcp://IP:9559] [--follow]
[--config FILE] [--connect tcp/HOST:PORT] [--namespace NS] [--rate HZ]
[--allow-not-awake]``.

It connects to the router (waiting up to ``--wait`` seconds), answers
``<ns>/bridge/execute`` and ``<ns>/bridge/stop`` (the operator's stop:
``armplan stop``; :mod:`bridge.service`), with ``--follow`` also plays
every trajectory published on ``<ns>/plan/trajectory``
(:mod:`bridge.follower`), and runs until SIGTERM or SIGINT (or its launcher
dies). Told to stop, it sends no new command: a request in its approach is
answered ``service_unavailable`` ("the bridge is stopping; ...") once the
approach ends, its trajectory not sent; a trajectory playing is watched to
its end and answered, for up to ``STOP_LIMIT`` (30 s): one that would play
longer is stopped then (its arm's motion tasks killed, not left playing
unwatched) and answered ``service_unavailable`` ("the bridge is stopping;
it stopped the arm at about t = ..."; see
:meth:`~bridge.service.BridgeService.stop`). The robot is reached on
demand: the bridge starts without it, and a robot that went away is
connected again at the next request. The robot's address: ``--robot``,
else ``$ARMPLAN_ROBOT``, else the simulated NAO at ``tcp://127.0.0.1:9559``
(:mod:`bridge.route`). Importing ``bridge`` first loads libqi before
pinocchio (see shared/libqi.py).
"""

from __future__ import annotations

import argparse
import logging
from collections.abc import Sequence

from bridge.address import ROBOT_ENV, robot_url
from bridge.awake import ALLOW_NOT_AWAKE
from bridge.claim import sole_bridge
from bridge.follower import TrajectoryFollower
from bridge.frames import DEFAULT_RATE, check_rate
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.service import BridgeService
from shared.bus import Bus, ServiceHost
from shared.bus.options import add_connect_options, add_router_wait_option
from shared.bus.process import (
    add_common_arguments,
    freeze_set_up,
    start_process,
    wait_for,
)
from shared.bus.process_config import process_config
from shared.bus.robot_routes import BRIDGE
from shared.command_line import ArgumentParser
from shared.errors import ArmplanError, ServiceUnavailableError

log = logging.getLogger("armplan.bridge")


def parser() -> argparse.ArgumentParser:
    """The bridge process's command line."""
    p = ArgumentParser(
        prog="python -m bridge.serve",
        description="The armplan robot bridge on Zenoh.",
    )
    add_common_arguments(p)
    add_connect_options(p)
    add_router_wait_option(p)
    p.add_argument(
        "--robot",
        metavar="URL",
        help=f"the robot's NAOqi address, e.g. tcp://IP:9559 for a real NAO "
        f"(default: ${ROBOT_ENV}, else the simulated NAO on tcp://127.0.0.1:9559)",
    )
    p.add_argument(
        "--follow",
        action="store_true",
        help="also play every trajectory published on <ns>/plan/trajectory",
    )
    p.add_argument(
        "--rate", type=float, default=DEFAULT_RATE, help="frame rate [Hz] (25)"
    )
    p.add_argument(
        ALLOW_NOT_AWAKE,
        action="store_true",
        help="play even on a robot that is not awake (ALMotion.robotIsWakeUp() "
        "false: resting, crouched or fallen); only for a robot held up by other "
        "means",
    )
    return p


def run(args: argparse.Namespace) -> None:
    """Serve until asked to stop (``start_process`` installed the handlers)."""
    stop = start_process(args.log_level)
    check_rate(args.rate)
    url = robot_url(args.robot)
    # another user's file, or another namespace: cut off, yet moving the robot
    config = process_config(args, BRIDGE)
    with NaoqiClient(url) as client:  # at its end, waits for the stops
        try:
            bus = Bus.connect(config, wait=args.wait, stop=stop)
        except ServiceUnavailableError:
            if not stop.is_set():
                raise
            log.info("bridge: asked to stop before a router answered")
            return
        with bus, sole_bridge(bus, stop):
            bridge = RobotBridge(
                client, rate=args.rate, require_awake=not args.allow_not_awake
            )
            service = BridgeService(bus, bridge)
            follower = TrajectoryFollower(service, args.rate) if args.follow else None
            freeze_set_up()  # before the token: no caller waits for it
            with ServiceHost(bus, BRIDGE, service.endpoints()):
                log.info("bridge: robot at %s", url)
                if follower is not None:
                    follower.start()
                try:
                    wait_for(stop)
                finally:
                    service.stop()  # no new command; answer the one in flight
                    if follower is not None:
                        follower.stop()
                    client.wait_stopped()  # holding the bridge's token meanwhile


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; 0 after a stop request, 1 on an error at start.

    An error at start: a configuration error, or another bridge running in
    the namespace.
    """
    args = parser().parse_args(argv)
    try:
        run(args)
    except ArmplanError as error:
        log.error("bridge: %s", error.message)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
