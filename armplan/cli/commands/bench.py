"""``armplan bench``: speed beside peers measured in the same run."""

from __future__ import annotations

import argparse

from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import add_json
from shared.errors import InvalidInputError

ORDER = 90
HELP = "measure speed beside peers run in the same process (no timed tests)"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``bench``."""
    parser = commands.add_parser("bench", help=HELP, description=HELP)
    parser.add_argument(
        "--targets", type=int, default=100, help="IK targets (default 100)"
    )
    parser.add_argument("--seed", type=int, default=7, help="random seed (default 7)")
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the benchmarks and print their figures and ratios."""
    from armplan.bench import ik_cost

    if args.targets < 1:
        raise InvalidInputError("--targets must be at least 1", field="targets")
    cost = ik_cost.run(args.targets, args.seed)
    figures = {
        "targets": args.targets,
        "ik_per_target_ms": cost.ours.mean * 1e3,
        "ik_per_target_p99_ms": cost.ours.percentile(99) * 1e3,
        "slsqp_per_target_ms": cost.peer.mean * 1e3,
        "speedup_vs_slsqp": cost.peer.mean / cost.ours.mean,
        "gpm_step_per_point_us": cost.step.mean * 1e6,
        "ik_reached_fraction": cost.ours_reached,
        "slsqp_reached_fraction": cost.peer_reached,
        "tpe_gap_on_common_targets_j": cost.tpe_gap,
    }
    if args.json:
        print_json(figures)
        return 0
    print_table(
        ("measure", "armplan", "scipy SLSQP (peer)", "peer / armplan"),
        [
            (
                "IK per target [ms]",
                figures["ik_per_target_ms"],
                figures["slsqp_per_target_ms"],
                figures["speedup_vs_slsqp"],
            ),
            (
                "targets reached within 0.1 mm",
                cost.ours_reached,
                cost.peer_reached,
                "-",
            ),
            ("TPE ours - peer, both reached [J]", cost.tpe_gap, "-", "-"),
            (
                "one eq. 14 step, per path point [us]",
                figures["gpm_step_per_point_us"],
                "-",
                "-",
            ),
        ],
    )
    return 0
