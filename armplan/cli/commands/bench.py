"""``armplan bench``: speed beside peers measured in the same run.

Two benchmarks, each timed beside peers doing the same work in this process:
the IK per target beside scipy's SLSQP (:mod:`armplan.bench.ik_cost`), and
planning a one-second reach end to end beside toppra's timing and ikpy's IK
of the same path (:mod:`armplan.bench.plan_cost`). A progress bar runs on
stderr while they do; ``--json`` prints every figure on stdout.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import TYPE_CHECKING

from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import add_json
from shared.errors import InvalidInputError

if TYPE_CHECKING:
    from armplan.bench.ik_cost import IKCost
    from armplan.bench.plan_cost import PlanCost

ORDER = 90
HELP = "measure speed beside peers run in the same process (no timed tests)"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``bench``."""
    parser = commands.add_parser("bench", help=HELP, description=HELP)
    parser.add_argument(
        "--targets", type=int, default=100, help="IK targets (default 100)"
    )
    parser.add_argument("--seed", type=int, default=7, help="random seed (default 7)")
    parser.add_argument(
        "--repeats",
        type=int,
        default=20,
        help="timed plans per method, toppra calls and calls per plan part "
        "(default 20)",
    )
    parser.add_argument(
        "--ikpy-passes",
        type=int,
        default=1,
        help="timed ikpy passes over the reach's path (default 1; each takes seconds)",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the benchmarks and print their figures and ratios."""
    from armplan.bench import ik_cost, plan_cost
    from armplan.bench.progress import progress_bar

    for name in ("targets", "repeats", "ikpy_passes"):
        if getattr(args, name) < 1:
            option = "--" + name.replace("_", "-")
            raise InvalidInputError(f"{option} must be at least 1", field=name)
    with progress_bar() as bar:
        ik_task = bar.add_task("IK beside scipy SLSQP", total=3 * args.targets)
        cost = ik_cost.run(args.targets, args.seed, lambda: bar.advance(ik_task))
        plan_task = bar.add_task(
            "one-second reach beside toppra and ikpy",
            total=plan_cost.steps(args.repeats, args.ikpy_passes),
        )
        planning = plan_cost.run(
            args.repeats, args.ikpy_passes, lambda: bar.advance(plan_task)
        )
    figures = _ik_figures(args.targets, cost) | planning.figures()
    if args.json:
        print_json(figures)
        return 0
    _print_ik(cost, figures)
    _print_planning(planning)
    return 0


def _ik_figures(targets: int, cost: IKCost) -> dict[str, float]:
    """The IK benchmark's JSON figures [ms, us, J], ratio peer / armplan."""
    return {
        "targets": targets,
        "ik_per_target_ms": cost.ours.mean * 1e3,
        "ik_per_target_p99_ms": cost.ours.percentile(99) * 1e3,
        "slsqp_per_target_ms": cost.peer.mean * 1e3,
        "speedup_vs_slsqp": cost.peer.mean / cost.ours.mean,
        "gpm_step_per_point_us": cost.step.mean * 1e6,
        "ik_reached_fraction": cost.ours_reached,
        "slsqp_reached_fraction": cost.peer_reached,
        "tpe_gap_on_common_targets_j": cost.tpe_gap,
    }


def _print_ik(cost: IKCost, figures: dict[str, float]) -> None:
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


def _print_planning(cost: PlanCost) -> None:
    """The one-second reach: whole plans beside the peers, then the parts."""
    f = cost.figures()
    plan, timing = f["plan_mp_ms"], f["part_timing_ms"]
    tracking = f["part_tracking_ms"]
    sys.stdout.write(
        f"\none-second reach ({cost.points} path points, a {cost.duration:.2f} s "
        f"trajectory), medians [ms]; load average {cost.load_average[0]:.1f} -> "
        f"{cost.load_average[1]:.1f} on {os.cpu_count()} CPUs:\n"
    )
    print_table(
        ("measure", "armplan", "peer", "peer / armplan"),
        [
            ("plan, method mp", plan, "-", "-"),
            ("plan, least-norm baseline", f["plan_least_norm_ms"], "-", "-"),
            ("plan, single baseline", f["plan_single_ms"], "-", "-"),
            _versus("whole plan vs toppra timing", plan, f, "toppra", "plan"),
            _versus("whole plan vs ikpy IK", plan, f, "ikpy", "plan"),
            _versus("Ruckig timing vs toppra", timing, f, "toppra", "timing"),
            _versus("IK tracking vs ikpy", tracking, f, "ikpy", "tracking"),
            ("ikpy: points within 0.1 mm", "-", f["ikpy_reached_fraction"], "-"),
        ],
    )
    sys.stdout.write("\nparts of the mp plan, each timed alone:\n")
    print_table(
        ("part", "median [ms]", "per path point [us]"),
        [
            ("wrist path", f["part_wrist_path_ms"], "-"),
            ("decision + IK tracking", f["part_decide_and_track_ms"], "-"),
            ("  IK tracking alone", tracking, f["ik_tracking_per_point_us"]),
            ("  decision (the difference)", "-", f["decision_per_point_us"]),
            ("timing (Ruckig)", timing, "-"),
            ("JointPath + Trajectory messages", f["part_messages_ms"], "-"),
        ],
    )


def _versus(
    label: str, ours: float, figures: dict[str, float], peer: str, part: str
) -> tuple[str, float, float, float]:
    """A row: ours [ms], the peer's [ms], and peer / ours."""
    return (label, ours, figures[f"{peer}_ms"], figures[f"{peer}_over_{part}"])
