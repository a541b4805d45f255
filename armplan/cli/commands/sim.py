"""``armplan sim``: run the simulated NAO (ALMotion over NAOqi) in the foreground."""

from __future__ import annotations

import argparse
import os
import sys

from shared.sim_options import add_sim_options, check_sim_options, sim_argv

ORDER = 70
HELP = "run the simulated NAO, serving ALMotion over NAOqi until Ctrl-C"
#: Same defaults as ``python -m bridge.sim``, which this command becomes.
DEFAULT_LISTEN = "tcp://127.0.0.1:9559"
PERIOD = 0.02


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``sim``."""
    parser = commands.add_parser("sim", help=HELP, description=HELP)
    parser.add_argument(
        "--listen",
        default=DEFAULT_LISTEN,
        help=f"NAOqi address to serve at (default {DEFAULT_LISTEN}; port 0: any)",
    )
    parser.add_argument("--log", default=None, help="JSON-lines log file")
    parser.add_argument(
        "--period", type=float, default=PERIOD, help="control cycle [s] (default 0.02)"
    )
    add_sim_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Become ``python -m bridge.sim``.

    A fresh interpreter loads libqi before pinocchio, which this one has
    loaded already (see shared/libqi.py). The address (well formed, free,
    local), the period, the sag, the grip and the log file are checked here
    first, so that a bad one is this command's typed error and nothing
    starts. Ctrl-C, SIGTERM and SIGHUP are held across the ``exec`` (see
    :mod:`armplan.cli.held_interrupt`): the sim takes them once it can
    stop, and exits 130 ("interrupted"), 143 ("terminated") or 129 ("hung
    up") without a traceback.
    """
    from armplan.cli.held_interrupt import hold_interrupt
    from bridge.address import check_listen_url
    from bridge.sim.cycle import check_period
    from bridge.sim.listen import check_can_listen
    from bridge.sim.log import check_log_file

    check_listen_url(args.listen)
    check_period(args.period)
    check_sim_options(args)
    check_can_listen(args.listen)
    if args.log is not None:
        check_log_file(args.log)
    argv = [sys.executable, "-m", "bridge.sim", "--listen", args.listen]
    argv += ["--period", str(args.period), "--prog", "armplan"]
    if args.log is not None:
        argv += ["--log", args.log]
    argv += sim_argv(args)
    sys.stdout.flush()
    sys.stderr.flush()
    hold_interrupt()
    os.execv(sys.executable, argv)
    return 0  # pragma: no cover (execv does not return)
