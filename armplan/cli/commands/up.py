"""``armplan up``: start the router and every service; stop them all on a signal.

``--namespace NS`` runs them all (services, bridge) under ``NS`` instead of
the config's namespace, e.g. a second system on a router another one uses.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import threading
from pathlib import Path

from armplan.cli.output import say
from armplan.cli.unsecured import check_plain_listen, check_unsecured
from armplan.launch import SERVICES, Launcher
from armplan.launch.robot import SIM_LISTEN, RobotStack
from shared.bus import Bus, BusConfig, load_config
from shared.bus.listen_clash import clashes
from shared.bus.options import add_config_option, add_namespace_option, with_namespace
from shared.bus.robot_routes import EXECUTE
from shared.errors import InvalidInputError
from shared.stop_signals import stop_on_signals

ORDER = 80
HELP = "start the Zenoh router and every service; Ctrl-C or SIGTERM stops them all"
#: Pause between checks on the children while running [s].
POLL = 0.2
#: Exit code once stopped if a child had exited while running (none restarts).
EXITED_WHILE_RUNNING = 1


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``up``."""
    parser = commands.add_parser("up", help=HELP, description=HELP)
    add_config_option(parser)
    parser.add_argument(
        "--listen",
        action="append",
        metavar="ENDPOINT",
        help="router endpoint (default tcp/127.0.0.1:7447, from the config)",
    )
    add_namespace_option(
        parser,
        "key namespace of every process started (default: the config's, armplan)",
    )
    parser.add_argument(
        "--only",
        nargs="+",
        metavar="SERVICE",
        choices=[s.name for s in SERVICES],
        help="start only these services (default: all)",
    )
    parser.add_argument(
        "--model",
        metavar="FILE",
        help="the fit service starts with this motion model (from 'armplan fit "
        "-o'), checked first; default: the one it served before, else the shipped",
    )
    _add_robot_arguments(parser)
    parser.set_defaults(run=run)


def _add_robot_arguments(parser: argparse.ArgumentParser) -> None:
    """The robot side: the sim, the bridge, the robot, follow mode."""
    parser.add_argument(
        "--with-sim",
        action="store_true",
        help=f"also start the simulated NAO on {SIM_LISTEN} and the bridge to it",
    )
    parser.add_argument(
        "--sim-listen",
        metavar="URL",
        help=f"where the simulated NAO serves, with --with-sim (default "
        f"{SIM_LISTEN}; port 0: any free one)",
    )
    parser.add_argument(
        "--with-bridge",
        action="store_true",
        help="also start the bridge (robot: --robot, $ARMPLAN_ROBOT or the sim's)",
    )
    parser.add_argument(
        "--robot",
        metavar="URL",
        help="a real NAO's address, e.g. tcp://IP:9559 (implies --with-bridge)",
    )
    parser.add_argument(
        "--follow",
        action="store_true",
        help="the bridge also plays every trajectory the planner publishes",
    )
    parser.add_argument(
        "--allow-not-awake",
        action="store_true",
        help="the bridge plays even on a robot that is not awake "
        "(robotIsWakeUp() false); only for a robot held up by other means",
    )


def run(args: argparse.Namespace) -> int:
    """Start everything, print where it listens, run until SIGTERM/SIGINT/SIGHUP.

    Returns:
        0, or ``EXITED_WHILE_RUNNING`` (1) if a child exited while running
        (reported then, not restarted), named on the last line.
    """
    config = with_namespace(load_config(args.config), args.namespace)
    check_unsecured(config, "up")  # the file's own endpoints, before --listen
    if args.listen:
        check_plain_listen(args.listen, "up")
        _check_each_once(args.listen)
        config = config.with_endpoints(tuple(args.listen), "--listen")
    else:
        check_plain_listen(config.endpoints, "up", f"{config.source} endpoint")
    if args.robot is not None:
        from bridge.address import check_robot_url

        check_robot_url(args.robot)  # before anything starts
    sim_listen = _sim_listen(args)
    fit_args = _fit_args(args)
    stop = stop_on_signals()
    launcher = Launcher(config, args.only, stop=stop, service_args=fit_args)
    # checked before anything starts
    robot_stack = _robot_stack(args, config, stop, sim_listen)
    # starts; stops everything on the way out (the robot side first)
    with launcher, robot_stack as robot:
        _print_started(launcher, config, robot)
        exited = _watch(launcher, robot, stop)
    if not exited:
        say("armplan up: stopped every process")
        return 0
    # a supervisor (systemd Restart=on-failure, docker) learns it from the code
    say(f"armplan up: stopped every process; exited while running: {exited}")
    return EXITED_WHILE_RUNNING


def _check_each_once(endpoints: list[str]) -> None:
    """Refuse an endpoint given or spelt twice: the router would clash with itself.

    ``tcp/localhost:P`` is ``tcp/127.0.0.1:P`` (``shared.bus.listen_clash``).

    Raises:
        InvalidInputError: naming the endpoints given more than once.
    """
    twice = list(dict.fromkeys(e for e in endpoints if endpoints.count(e) > 1))
    if twice:
        raise InvalidInputError(
            f"--listen {', '.join(twice)} given more than once: the router "
            "cannot listen twice on one endpoint; give each once",
            field="listen",
            endpoints=twice,
        )
    found = clashes(endpoints)
    if found:
        first, second = found[0]
        raise InvalidInputError(
            f"--listen {first} and {second} are one socket (one transport, "
            "port and address): the router cannot listen twice on it; give "
            "one of them",
            field="listen",
            endpoints=[first, second],
        )


def _sim_listen(args: argparse.Namespace) -> str:
    """Where the sim is to serve, checked; ``--sim-listen`` only with ``--with-sim``.

    Raises:
        InvalidInputError: ``--sim-listen`` without ``--with-sim`` (the bridge
            went to the default robot, and without a bridge nothing started),
            or a malformed URL (as ``check_listen_url``).
    """
    if not args.with_sim:
        if args.sim_listen is not None:
            raise InvalidInputError(
                "--sim-listen is where the simulated NAO serves: add --with-sim "
                "to start it (a bridge to another robot: --robot URL)",
                field="sim_listen",
            )
        return SIM_LISTEN
    from bridge.address import check_listen_url

    url = SIM_LISTEN if args.sim_listen is None else args.sim_listen
    check_listen_url(url)
    return url


def _fit_args(args: argparse.Namespace) -> dict[str, list[str]]:
    """``--model`` for the fit service, the file checked here first.

    Raises:
        ModelFileError: the file is no valid motion model, or one the
            decision cannot use (as the fit service checks it at start).
        InvalidInputError: ``--model`` while ``--only`` leaves fit out.
    """
    if args.model is None:
        return {}
    if args.only is not None and "fit" not in args.only:
        raise InvalidInputError(
            "--model is the fit service's model, and --only leaves fit out",
            field="model",
        )
    from services.fit.decidable import load_decidable

    load_decidable(args.model)  # a bad file stops everything before it starts
    return {"fit": ["--model", str(Path(args.model).resolve())]}


def _robot_stack(
    args: argparse.Namespace,
    config: BusConfig,
    stop: threading.Event,
    sim_listen: str,
) -> RobotStack | contextlib.nullcontext[None]:
    """The sim and the bridge if asked for (not started yet), else nothing."""
    if not (args.with_sim or args.with_bridge or args.robot or args.follow):
        if args.allow_not_awake:
            raise InvalidInputError(
                "--allow-not-awake is the bridge's: start one (--with-bridge, "
                "--robot, --with-sim or --follow)",
                field="allow_not_awake",
            )
        return contextlib.nullcontext()
    return RobotStack(
        config,
        robot=args.robot,
        sim=args.with_sim,
        sim_listen=sim_listen,
        follow=args.follow,
        stop=stop,
        allow_not_awake=args.allow_not_awake,
    )


def _print_started(
    launcher: Launcher, config: BusConfig, robot: RobotStack | None
) -> None:
    assert launcher.router is not None
    say(
        f"router   pid {launcher.router.pid:<7d} listening on "
        f"{', '.join(config.endpoints)} (namespace {config.namespace}, "
        f"config {config.source})"
    )
    for spec in launcher.specs:
        keys = ", ".join(r.key(config.namespace) for r in spec.routes)
        pid = launcher.services[spec.name].pid
        say(f"{spec.name:<8} pid {pid:<7d} {keys}")
    if robot is not None:
        _print_robot(robot, config)
    with Bus.connect(config) as bus:
        alive = ", ".join(bus.alive())
    say(f"armplan up: ready, alive: {alive}; Ctrl-C or SIGTERM stops them all")


def _print_robot(robot: RobotStack, config: BusConfig) -> None:
    pids = robot.processes()
    if "sim" in pids:
        say(f"{'sim':<8} pid {pids['sim']:<7d} ALMotion over NAOqi at {robot.url}")
    key = EXECUTE.key(config.namespace)
    say(f"{'bridge':<8} pid {pids['bridge']:<7d} {key} -> robot {robot.url}")


def _watch(launcher: Launcher, robot: RobotStack | None, stop: threading.Event) -> str:
    """Wait for a stop request; report children that exit meanwhile.

    Returns:
        Those children, ``"sim (pid 12) with code -9, ..."``; ``""`` if none.
    """
    reported: dict[int, str] = {}
    while not stop.wait(POLL):
        for name, pid, how in _exited(launcher, robot):
            if pid not in reported and not stop.is_set():  # not the stop's doing
                reported[pid] = f"{name} (pid {pid}){how}"
                sys.stderr.write(f"armplan up: {name} (pid {pid}) exited{how}\n")
    return ", ".join(reported.values())


def _exited(launcher: Launcher, robot: RobotStack | None) -> list[tuple[str, int, str]]:
    """``(name, pid, " with code N")`` of each child that has exited."""
    gone = [(c.name, c.pid, f" with code {c.exit_code()}") for c in launcher.exited()]
    if robot is None:
        return gone
    return gone + [
        (name, pid, f" with code {code}") for name, pid, code in robot.exited()
    ]
