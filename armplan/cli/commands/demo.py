"""``armplan demo [--out DIR]``: the paper's handover task on the simulated NAO.

Starts the Zenoh router, every service, the simulated NAO, the bridge and the
recorder; plans the human-robot collaboration task through the planner
service; plays it through the bridge; writes ``trajectory.json``,
``behavior.xar`` (Choregraphe), ``play.py`` (Python export), ``report.json``
(tracking error per joint) and ``session.mcap`` into DIR; prints a summary
and stops every process, also on Ctrl-C or SIGTERM. A recording that failed
exits 1 with the recorder's reason, after the summary (the other files are
written). See ``armplan.demo``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from armplan.cli.output import say  # stdout gone (| head, closed terminal): quiet
from shared.bus.options import add_config_option

ORDER = 5
HELP = "run the paper's handover task on the simulated NAO and write the results"
#: Where the demo writes by default (relative to the current folder).
DEFAULT_OUT = "armplan-demo"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``demo``."""
    parser = commands.add_parser("demo", help=HELP, description=__doc__)
    parser.add_argument(
        "--out",
        metavar="DIR",
        default=DEFAULT_OUT,
        help=f"folder for the results (default ./{DEFAULT_OUT}/)",
    )
    parser.add_argument(
        "--task", metavar="FILE", help="task file (default: the paper's handover)"
    )
    parser.add_argument(
        "--robot",
        metavar="URL",
        help="play on a real NAO at tcp://IP:9559 instead of the simulated one",
    )
    parser.add_argument(
        "--allow-not-awake",
        action="store_true",
        help="with --robot: play even on a NAO that is not awake "
        "(robotIsWakeUp() false); only for a robot held up by other means",
    )
    parser.add_argument(
        "--listen",
        metavar="ENDPOINT",
        help="the router's endpoint (default: a free port on 127.0.0.1)",
    )
    add_config_option(parser)
    parser.add_argument(
        "--no-record", action="store_true", help="do not record session.mcap"
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the demo; print progress, then the summary."""
    from armplan.cli.termination import terminate_on_sigterm
    from armplan.cli.unsecured import check_plain_listen, check_unsecured
    from armplan.demo import DEFAULT_TASK, DemoOptions, run_demo, summary_lines
    from armplan.launch import free_endpoint
    from shared.bus import load_config
    from shared.output_paths import check_output_folder

    config = load_config(args.config)
    check_unsecured(config, "demo")  # the file's own endpoints, before --listen
    if args.listen:
        check_plain_listen([args.listen], "demo")
    out = check_output_folder(args.out)
    terminate_on_sigterm()  # stops everything as Ctrl-C does
    started = time.monotonic()
    endpoint = args.listen or free_endpoint()
    options = DemoOptions(
        config=config.with_endpoints((endpoint,), "--listen"),
        out=out,
        robot=_robot(args.robot),
        record=not args.no_record,
        task=Path(args.task) if args.task else DEFAULT_TASK,
        allow_not_awake=args.allow_not_awake,
    )
    result = run_demo(options, say)
    for line in summary_lines(result):
        say(line)
    if result.recording_error is not None:  # every other file is whole
        raise result.recording_error
    took = time.monotonic() - started
    say(f"armplan demo: done in {took:.1f} s; every process stopped")
    return 0


def _robot(url: str | None) -> str | None:
    """The checked robot address, or ``None`` for the simulated NAO."""
    if url is None:
        return None
    from bridge.address import check_robot_url

    return check_robot_url(url)
