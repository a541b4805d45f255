"""``armplan bench``: speed beside peers measured in the same run.

Three benchmarks, each timed beside peers doing the same work in this run:

- the IK per target beside scipy's SLSQP (same measure) and ikpy, on the
  same targets (:mod:`armplan.bench.ik_cost`);
- planning a one-second reach in-process beside toppra's timing and ikpy's
  IK of the same path (:mod:`armplan.bench.plan_cost`);
- the same reach through a real router and every service on a free loopback
  port, by 1, 8 and 50 concurrent clients, beside in-process plans
  (:mod:`armplan.bench.service_latency`); ``--no-services`` skips it.

A progress bar runs on stderr while they do; ``--json`` prints every figure
on stdout, flat, with the machine's processor model, CPUs and load average
over the run.
"""

from __future__ import annotations

import argparse
import os

from armplan.bench.machine import cpu_model
from armplan.cli.output import print_json
from armplan.cli.parsing import add_json
from shared.bus.queue_room import MOST_AT_ONCE, check_queue_room
from shared.compiled import running_compiled
from shared.errors import InvalidInputError

ORDER = 90
HELP = "measure speed beside peers run in the same process (no timed tests)"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``bench``."""
    parser = commands.add_parser("bench", help=HELP, description=HELP)
    parser.add_argument(
        "--targets",
        type=int,
        default=100,
        help=f"IK targets, 1 to {MOST_TARGETS} (default 100)",
    )
    parser.add_argument("--seed", type=int, default=7, help="random seed (default 7)")
    parser.add_argument(
        "--repeats",
        type=int,
        default=20,
        help="timed plans per method, toppra calls and calls per plan part, "
        f"1 to {MOST_REPEATS} (default 20)",
    )
    parser.add_argument(
        "--ikpy-passes",
        type=int,
        default=1,
        help=f"timed ikpy passes over the reach's path, 1 to {MOST_IKPY_PASSES} "
        "(default 1; each takes seconds)",
    )
    parser.add_argument(
        "--plans",
        type=int,
        default=100,
        help=f"plans in-process, 1 to {MOST_PLANS} (default 100); through the "
        "services, for each client count, PLANS but at least 10 per client",
    )
    parser.add_argument(
        "--clients",
        type=_client_counts,
        default=[1, 8, 50],
        help="concurrent clients through the services, comma-separated "
        "(default 1,8,50)",
    )
    parser.add_argument(
        "--no-services",
        dest="services",
        action="store_false",
        help="skip the benchmark through the services (starts no processes)",
    )
    add_json(parser)
    parser.set_defaults(run=run)


#: Most concurrent clients in one row: the planner lets this many requests
#: wait (its queue limit); more would be answered ``service_busy`` after all
#: the other work of the run.
MOST_CLIENTS = MOST_AT_ONCE


#: Most IK targets: all are drawn and each one's eq. 14 run prepared up
#: front (about 5 kB each); ``--targets 100000000`` grew the process by
#: gigabytes, no progress shown, before timing the first. 10000 take about
#: 25 min with both peers.
MOST_TARGETS = 10_000

#: Most rounds of the in-process planning benchmark (``--repeats``) and most
#: plans (``--plans``): every timed call is made into one list before the
#: first is timed (a round is 11 calls; 16 bytes a call), so ``--repeats
#: 100000000`` grew the process by gigabytes, no progress shown, before
#: timing anything. 10000 rounds take 4-8 min, 10000 plans about 2 min a
#: row through the services.
MOST_REPEATS = 10_000
MOST_PLANS = 10_000
#: Most ikpy passes: made into one list too, and each takes seconds (100
#: about 8 min); ``--ikpy-passes 1000000000`` took gigabytes before the first.
MOST_IKPY_PASSES = 100

#: Per count option, its most and why there is one.
MOST: dict[str, tuple[int, str]] = {
    "targets": (
        MOST_TARGETS,
        "every target is drawn and prepared before the first is timed",
    ),
    "repeats": (MOST_REPEATS, "every round's calls are made before the first is timed"),
    "plans": (MOST_PLANS, "every plan's call is made before the first is timed"),
    "ikpy_passes": (
        MOST_IKPY_PASSES,
        "every pass's call is made before the first is timed, and each takes seconds",
    ),
}


def _client_counts(text: str) -> list[int]:
    """``"1,8,50"`` -> ``[1, 8, 50]``; each 1..``MOST_CLIENTS``, each once.

    A count given twice would run twice and print two rows, but its
    figures are kept under one key (``services_8_p50_ms``): refused.
    """
    try:
        counts = [int(part) for part in text.split(",")]
    except ValueError:
        counts = []
    if not counts or min(counts) < 1:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a comma-separated list of client counts, "
            f"each 1..{MOST_CLIENTS}"
        )
    repeated = sorted({c for c in counts if counts.count(c) > 1})
    if repeated:
        raise argparse.ArgumentTypeError(
            f"{text!r} gives {', '.join(map(str, repeated))} clients more than "
            "once: each count is one row, give each once"
        )
    try:
        give = f"each count 1..{MOST_CLIENTS}"
        check_queue_room(max(counts), "clients", give, field="clients")
    except InvalidInputError as error:
        raise argparse.ArgumentTypeError(error.message) from None
    return counts


def run(args: argparse.Namespace) -> int:
    """Run the benchmarks and print their figures and ratios."""
    from armplan.bench import report
    from armplan.bench.extras import require

    _check_counts(args)
    if args.seed < 0:  # numpy's generators take none
        raise InvalidInputError(
            f"--seed must be 0 or more, got {args.seed}", field="seed"
        )
    require("toppra", "ikpy")  # the peers, before any work
    figures = measure(args)
    processor = cpu_model()
    if args.json:
        print_json({"cpu_model": processor} | figures)
        return 0
    report.print_machine(figures, processor)
    report.print_ik(figures)
    report.print_planning(figures)
    if args.services:
        report.print_services(figures, args.clients)
    report.print_bars(figures, args.clients if args.services else [])
    return 0


def _check_counts(args: argparse.Namespace) -> None:
    """Refuse a count below 1, or above its most (:data:`MOST`), naming it."""
    for name in ("targets", "repeats", "ikpy_passes", "plans"):
        if getattr(args, name) < 1:
            option = "--" + name.replace("_", "-")
            raise InvalidInputError(f"{option} must be at least 1", field=name)
    for name, (most, why) in MOST.items():
        if getattr(args, name) > most:
            option = "--" + name.replace("_", "-")
            raise InvalidInputError(
                f"{option} must be 1..{most}, got {getattr(args, name)}: {why}",
                field=name,
            )


def measure(args: argparse.Namespace) -> dict[str, float]:
    """Every benchmark's figures, flat, under one progress bar."""
    from armplan.bench import ik_cost, plan_cost, service_latency
    from armplan.cli.progress import progress_bar

    load_start = os.getloadavg()[0]
    with progress_bar() as bar:
        task = bar.add_task(
            "IK beside SLSQP and ikpy", total=ik_cost.steps(args.targets)
        )
        figures = ik_cost.run(
            args.targets, args.seed, lambda: bar.advance(task)
        ).figures()
        total = plan_cost.steps(args.repeats, args.ikpy_passes)
        task = bar.add_task("one-second reach beside toppra and ikpy", total=total)
        figures |= plan_cost.run(
            args.repeats, args.ikpy_passes, lambda: bar.advance(task)
        ).figures()
        if args.services:
            total = service_latency.steps(args.plans, args.clients)
            task = bar.add_task("the reach through the services", total=total)
            figures |= service_latency.run(
                args.plans, args.clients, after=lambda: bar.advance(task)
            ).figures()
    return figures | {
        "cpus": float(os.cpu_count() or 0),
        "load_average_start": load_start,
        "load_average_end": os.getloadavg()[0],
        "compiled": float(running_compiled()),
    }
