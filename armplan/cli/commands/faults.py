"""``armplan faults``: the fault and load suite on the real processes.

Starts every process on a free 127.0.0.1 port (router, fit, decide, ik,
timing, planner, the simulated NAO, the bridge, the recorder); kills and
restarts each service, the bridge, the router and the recorder while clients
plan; sends a burst of concurrent plans; sends hypothesis-made bad inputs to
every queryable (the services' routes and the bridge's execute; the
simulated NAO is neither killed nor sent bad inputs, the recorder answers
no request). Prints one row per scenario: faults injected, requests sent,
succeeded, failed with a clear error, unclear errors, lost, crashes, and
what showed the fault. Exits 1 if any request was lost, answered with an
unclear error, any process crashed, or a scenario did not show what it
must (a restarted process serving again, the calls that needed a killed
one naming it, ...). See docs/faults.md.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from armplan.cli.output import print_json
from armplan.cli.parsing import add_json
from shared.bus.queue_room import MOST_AT_ONCE, check_queue_room
from shared.errors import ArmplanError, InvalidInputError

if TYPE_CHECKING:
    from armplan.faults import SuiteOptions

ORDER = 85
HELP = (
    "kill and restart every process but the simulated NAO, send bad inputs to "
    "the services and the bridge; print what was lost"
)


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``faults``."""
    parser = commands.add_parser("faults", help=HELP, description=__doc__)
    parser.add_argument(
        "--requests",
        type=int,
        default=60,
        metavar="N",
        help="requests per kill scenario: a third before, while down, after (60)",
    )
    parser.add_argument(
        "--concurrency",
        type=int,
        default=8,
        metavar="N",
        help="client threads sending them (8)",
    )
    parser.add_argument(
        "--burst",
        type=int,
        default=200,
        metavar="N",
        help="plan requests sent at once, at most the planner's queue limit "
        f"of {MOST_AT_ONCE} (200)",
    )
    parser.add_argument(
        "--examples",
        type=int,
        default=4,
        metavar="N",
        help="bad inputs of each of the 6 kinds per queryable (4)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, metavar="N", help="seed of the bad inputs (0)"
    )
    parser.add_argument(
        "--out",
        metavar="DIR",
        help="keep the logs and recordings here (default: a temporary folder); "
        "a folder already holding them (session.mcap, logs/...) is refused",
    )
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an earlier run's recordings and logs in --out",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the suite, print the table; 1 if anything was lost, crashed or unmet."""
    if importlib.util.find_spec("hypothesis") is None:
        raise ArmplanError(
            "armplan faults makes its bad inputs with hypothesis, from the "
            "development extra: pip install -c constraints.txt -e '.[dev]'",
            missing=["hypothesis"],
        )
    from armplan.faults import SuiteOptions
    from shared.output_paths import check_output_folder

    for name in ("requests", "concurrency", "examples"):
        if getattr(args, name) < 1:
            raise InvalidInputError(f"--{name} must be at least 1", field=name)
    if args.requests < 3:
        raise InvalidInputError("--requests must be at least 3", field="requests")
    if args.burst < 0:
        raise InvalidInputError("--burst must not be negative", field="burst")
    give = f"--burst 0..{MOST_AT_ONCE}"
    check_queue_room(args.burst, "plans at once (--burst)", give, field="burst")
    if args.seed < 0:
        raise InvalidInputError(
            f"--seed must be 0 or more, got {args.seed}", field="seed"
        )
    kept = None if args.out is None else check_output_folder(args.out)
    options = SuiteOptions(
        requests=args.requests,
        concurrency=args.concurrency,
        burst=args.burst,
        examples=args.examples,
        seed=args.seed,
    )
    if kept is not None:
        return _run(kept, options, args.json, args.overwrite)
    with tempfile.TemporaryDirectory(prefix="armplan-faults-") as out:
        return _run(Path(out), options, args.json, args.overwrite)


def _run(out: Path, options: SuiteOptions, as_json: bool, overwrite: bool) -> int:
    from rich.console import Console

    from armplan.cli.console import StdoutConsole
    from armplan.faults import json_report, passed, rich_table, run_suite
    from armplan.faults.tally import Tally

    err = Console(stderr=True)

    def report(tally: Tally) -> None:
        row = tally.row()
        err.print(
            f"[dim]{row['scenario']}: sent {row['sent']}, lost {row['lost']}, "
            f"crashes {row['crashes']}[/]"
        )

    load_start = os.getloadavg()[0]
    tallies = run_suite(out, options, report, overwrite=overwrite)
    load = (load_start, os.getloadavg()[0])
    if as_json:
        print_json(json_report(tallies, load))
    else:
        title = (
            f"armplan faults ({os.cpu_count()} CPUs, load average "
            f"{load[0]:.1f} at the start, {load[1]:.1f} at the end)"
        )
        StdoutConsole(width=200).print(rich_table(tallies, title))
        verdict = "passed" if passed(tallies) else "FAILED"
        sys.stdout.write(f"armplan faults: {verdict}\n")
    return 0 if passed(tallies) else 1
