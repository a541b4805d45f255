"""``armplan decide``: the motion decision along a reach or a wrist path.

    armplan decide --target X Y Z [--arm right|left] [--start Q1..Q5]
                   [--palm X Y Z] [--duration S] [--model FILE]
                   [--json] [--plot decision.png]
    armplan decide --wrist-path FILE.csv [...]
    armplan decide --grid [--demos DEMOS.mcap] [--json]
    armplan decide --target X Y Z | --wrist-path FILE.csv --remote [...]

With ``--target`` the wrist path is the planner's human-like reach from the
start posture (default: the arm hanging at rest) to the target, at 100 Hz and
``--duration`` seconds long, by default as long as ``armplan plan`` takes for
it at human pace (``services.timing.reach_duration`` of the move the planner
tracks: the same 0.69 s for ``0.12 -0.13 0.05`` from rest); with
``--wrist-path`` it is read from a CSV file (header ``t,x,y,z``, torso frame,
s and m). The decision runs inside the IK tracker (``services.decide.path``)
and prints, per run of one primitive, its times and points (``--json``: the
``Decision`` message, every point's primitive, matrix and every g).
``--plot`` draws it like the paper's Fig. 7. ``--grid`` prints the
Table-4-like sequences of primitives on the paper's 16 grid points for the
``--arm`` its header names (``--json``: ``arm``, and each point's wrist
target in the torso frame, ``wrist`` [m]); with
``--demos`` also the ``--arm``'s demonstrations' own sequences, with a count
of the reaches left out and why (recorded reaches have no grid point, the
other arm's are not this table's; a file with no reach of the arm, or none
that can enter the table, is refused).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armplan.cli.one_target import OneTarget
from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import add_arm, add_json, finite
from armplan.cli.remote import add_remote, is_remote
from shared.errors import DemoFileError, InvalidInputError
from shared.messages.base import unit_direction
from shared.output_paths import check_output_file
from shared.text.counted import agreeing, counted

if TYPE_CHECKING:
    from services.decide.grid_table import DemoRow, LeftOut

#: Decides along a path: (times [s] (n,), wrist positions [m] (n, 3), start
#: posture [rad] (5,)) -> (decision, last posture [rad], last wrist [m]).
Decide = Callable[
    [np.ndarray, np.ndarray, np.ndarray], tuple[Any, np.ndarray, np.ndarray]
]

ORDER = 25
HELP = "motion decision: which movement primitive drives each path point"
#: Sample rate of a reach [Hz].
RATE = 100.0


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``decide``."""
    parser = commands.add_parser("decide", help=HELP, description=HELP)
    add_arm(parser)
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument(
        "--target",
        action=OneTarget,
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="wrist goal [m]",
    )
    what.add_argument(
        "--wrist-path", metavar="FILE.csv", help="timed wrist path, header t,x,y,z"
    )
    what.add_argument(
        "--grid", action="store_true", help="Table-4-like table on the 16 grid points"
    )
    parser.add_argument(
        "--start", type=float, nargs=5, metavar="Q", help="start posture [rad]"
    )
    parser.add_argument(
        "--palm", type=float, nargs=3, metavar=("X", "Y", "Z"), help="palm direction"
    )
    parser.add_argument(
        "--duration",
        type=float,
        help="movement time of --target [s] (default: the planner's human pace "
        "for the reach, as armplan plan takes)",
    )
    parser.add_argument(
        "--model", metavar="FILE", help="motion model (default: shipped)"
    )
    parser.add_argument("--plot", metavar="FILE.png", help="draw the decision (Fig. 7)")
    parser.add_argument(
        "--demos",
        metavar="FILE.mcap",
        help="with --grid: also the --arm's demos' sequences",
    )
    add_json(parser)
    add_remote(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Decide and print."""
    from services.fit import default_model
    from services.fit.decidable import load_decidable

    _check_options(args)
    remote = is_remote(args)  # the service's model, not one loaded here
    model = (
        None
        if remote
        else load_decidable(args.model)  # a bad file is named
        if args.model
        else default_model()
    )
    if args.grid:
        return _grid(args, model)
    from services.decide.path import decide_path
    from services.planner.stages import model_digest
    from shared.robot import load_arm
    from shared.robot.postures import rest

    arm = load_arm(args.arm)
    start = (
        rest(arm.side) if args.start is None else np.array(finite(args.start, "start"))
    )
    arm.limits.check(start, where="in the start posture")
    palm = _palm(args.palm)
    plot = _plot_file(args.plot)

    def decide(times: np.ndarray, positions: np.ndarray, start: np.ndarray) -> Any:
        if model is None:  # --remote: the decide service decides with its model
            return _decide_remote(args, arm, times, positions, start, palm)
        decision, tracked = decide_path(
            model, arm, positions, start, palm=palm, times=times
        )
        named = {"model": model_digest(model)}  # as the decide service names it
        return decision.model_copy(update=named), tracked.q[-1], tracked.wrist[-1]

    times, positions, start = _path(args, arm, start, palm, decide)
    decision, _, wrist_end = decide(times, positions, start)
    if plot is not None:
        from services.decide.plot import plot_decision

        plot_decision(decision, plot, title=_title(args, positions))
    if args.json:
        print_json(decision.model_dump(mode="json"))
        return 0
    _print_runs(decision, wrist_end, positions)
    if plot is not None:
        sys.stdout.write(f"wrote {plot}\n")
    return 0


#: Options that shape one decision, not the --grid table.
ONE_DECISION = ("start", "palm", "duration", "plot")


def _check_options(args: argparse.Namespace) -> None:
    """Refuse options the chosen form would ignore, naming them."""
    if is_remote(args):
        for name, why in (
            ("grid", "--grid runs in this process"),
            ("model", "the decide service decides with the model it serves"),
        ):
            if getattr(args, name):
                raise InvalidInputError(
                    f"--{name} does not go with --remote: {why}", field=name
                )
    if args.grid:
        for name in ONE_DECISION:
            if getattr(args, name) is not None:
                raise InvalidInputError(
                    f"--{name} is for one decision (--target or --wrist-path); "
                    "--grid decides the reaches of the 16 grid points from rest",
                    field=name,
                )
        return
    if args.demos is not None:
        raise InvalidInputError(
            "--demos adds the demonstrations' sequences to --grid's table",
            field="demos",
        )
    if args.wrist_path and args.duration is not None:
        raise InvalidInputError(
            "--duration is the movement time of --target; --wrist-path keeps "
            "its own times",
            field="duration",
        )


def _plot_file(plot: str | None) -> Path | None:
    """The plot's file: a writable PNG path (checked before work)."""
    if plot is None:
        return None
    if Path(plot).suffix.lower() != ".png" or Path(plot).is_dir():
        raise InvalidInputError(
            f"--plot {plot!r}: name a .png file to write", field="plot"
        )
    return check_output_file(plot, field="plot")


def _palm(values: list[float] | None) -> np.ndarray | None:
    if values is None:
        return None
    finite(values, "palm")
    try:
        return np.array(unit_direction(values))
    except ValueError:
        raise InvalidInputError(
            "--palm must not be the zero vector", field="palm"
        ) from None


def _path(
    args: argparse.Namespace,
    arm: Any,
    start: np.ndarray,
    palm: np.ndarray | None,
    decide: Decide,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(times [s], positions [m], start posture [rad]) of the path to decide along.

    A CSV path starts at its first sample: as ``armplan plan`` does, the arm
    starts in the posture that puts the wrist there (``start`` itself if it
    does already). A reach to ``--target`` lasts ``--duration``, or the
    planner's human pace for it (``_human_pace``, with ``decide``).
    """
    from services.ik.solver import check_target
    from services.planner.path_reach import check_path_clear, check_path_within_reach
    from services.planner.pipeline import start_on_path
    from shared.messages import Method

    if args.wrist_path:
        from services.decide.wrist_csv import read_wrist_csv

        path = read_wrist_csv(args.wrist_path, arm.side)
        if palm is not None:
            path = path.model_copy(update={"palm": tuple(float(v) for v in palm)})
        check_path_within_reach(arm, path)
        check_path_clear(arm, path)
        start = start_on_path(arm, path, start, Method.MP)
        return np.array(path.times), np.array(path.positions), start
    from services.planner.wrist_path import reach_path

    if args.duration is not None and not 0.05 <= args.duration <= 60.0:
        raise InvalidInputError("--duration must be 0.05..60 s", field="duration")
    target = np.array(finite(args.target, "target"))
    check_target(arm, target)
    duration = args.duration
    if duration is None:
        duration = _human_pace(arm, start, target, palm, decide)
    reach = reach_path(arm, start, target, duration, RATE)
    return reach.times, reach.positions, start


def _human_pace(
    arm: Any,
    start: np.ndarray,
    target: np.ndarray,
    palm: np.ndarray | None,
    decide: Decide,
) -> float:
    """How long ``armplan plan`` takes for the reach at human pace [s].

    As the planner times it: the human law (``reach_duration``) for the move
    from ``start`` [rad], shape (5,), to the posture that tracking its wrist
    path (``reach_wrist_path``) with ``decide`` ends in; ``target`` [m] and
    ``palm`` (unit or ``None``) shape (3,), torso frame.
    """
    from services.planner.reach_path import reach_wrist_path
    from services.timing import reach_duration
    from shared.messages import ReachTarget

    goal = ReachTarget(
        position=tuple(float(v) for v in target),
        palm=None if palm is None else tuple(float(v) for v in palm),
    )
    path = reach_wrist_path(arm, start, goal)
    _, end, _ = decide(np.array(path.times), np.array(path.positions), start)
    return reach_duration(arm, start, end)


def _title(args: argparse.Namespace, positions: np.ndarray) -> str:
    goal = ", ".join(f"{v:.3f}" for v in positions[-1])
    return f"{args.arm} arm to ({goal}) m"


def _decide_remote(
    args: argparse.Namespace,
    arm: Any,
    times: np.ndarray,
    positions: np.ndarray,
    start: np.ndarray,
    palm: np.ndarray | None,
) -> tuple[Any, np.ndarray, np.ndarray]:
    """(decision, last posture [rad], last wrist [m]) from the services.

    The decide service decides; the ik service tracks the path with the
    decided primitives, as the decision's own tracking did, to give the
    arm's end.
    """
    from armplan.cli.remote import connect
    from shared.bus.routes import DECIDE, IK_PATH
    from shared.messages import DecideRequest, Method, PathIKRequest, WristPath

    path = WristPath(
        arm=arm.side,
        times=[float(t) for t in times],
        positions=[tuple(float(v) for v in p) for p in positions],
        palm=None if palm is None else tuple(float(v) for v in palm),
    )
    begin = tuple(float(v) for v in start)
    with connect(args) as bus:
        decision = bus.call(DECIDE, DecideRequest(path=path, start=begin))
        tracked = bus.call(
            IK_PATH,
            PathIKRequest(path=path, start=begin, method=Method.MP, decision=decision),
        )
    return decision, np.array(tracked.positions[-1]), np.array(tracked.wrist[-1])


def _print_runs(decision: Any, wrist_end: np.ndarray, positions: np.ndarray) -> None:
    from services.decide.grid_table import runs

    rows, at = [], 0
    for name, count in runs(decision.primitives):
        rows.append((name, decision.times[at], decision.times[at + count - 1], count))
        at += count
    print_table(("primitive", "from [s]", "to [s]", "points"), rows)
    error = float(np.linalg.norm(wrist_end - positions[-1]))
    sys.stdout.write(
        f"{counted(len(decision.times), 'point')}; "
        f"wrist {error * 1000:.3f} mm from the goal "
        "at the end\n"
    )


def _grid(args: argparse.Namespace, model: Any) -> int:
    from services.decide.grid_table import MIN_POINTS, grid_rows
    from shared.robot import Side

    side = Side.parse(args.arm)
    demo, left = _demo_table(args.demos, args.arm)
    rows = grid_rows(model, side)
    if args.json:
        print_json(
            {
                "arm": side.value,
                "nao": [r._asdict() for r in rows],
                "demonstrations": [r._asdict() for r in demo],
                "left_out": None
                if left is None
                else {"total": left.total, **left._asdict()},
            }
        )
        return 0
    sys.stdout.write(
        f"NAO's {side.value} arm, decision along the planner's reach from "
        f"hanging at rest (switches shorter than {MIN_POINTS} points counted apart):\n"
    )
    print_table(
        ("point", "time [s]", "primitives in order", "count", "short"),
        [
            (
                f"P{r.point}",
                r.duration,
                "  ->  ".join(r.sequence),
                len(r.sequence),
                r.short,
            )
            for r in rows
        ],
    )
    if demo:
        sys.stdout.write("\ndemonstrations (labels), most common sequence per point:\n")
        print_table(
            ("point", "time [s]", "primitives in order", "count", "share"),
            [
                (
                    f"P{r.point}",
                    r.duration,
                    "  ->  ".join(r.sequence),
                    len(r.sequence),
                    r.share,
                )
                for r in demo
            ],
        )
    if left is not None and left.total:
        sys.stdout.write(
            f"\n{left.total} of {left.of} demonstrated reaches left out of the "
            f"table: {left.describe()}\n"
        )
    return 0


def _demo_table(path: str | None, arm: str) -> tuple[list[DemoRow], LeftOut | None]:
    """(rows, reaches left out) of ``arm``'s demonstrations in ``path``, if given.

    Raises:
        DemoFileError: if the file holds no reach of ``arm`` (naming the arms
            it holds), or every reach of it is left out (recorded reaches
            have no grid point): the table asked for would be empty.
    """
    if path is None:
        return [], None
    from services.decide.grid_table import arms_of, demo_rows, left_out
    from shared.demos import read_demos
    from shared.robot import Side

    side = Side.parse(arm)
    demos = read_demos(path)
    present = arms_of(demos)
    if present and side not in present:
        held = " and ".join(s.value for s in present)
        raise DemoFileError(
            path,
            f"its {counted(len(demos.trials), 'reach', 'reaches')} "
            f"{agreeing(len(demos.trials), 'is', 'are')} of the {held} arm, "
            "none of the "
            f"{side.value} arm the table is for (--arm {side.value})",
            arms=[s.value for s in present],
            arm=side.value,
        )
    left = left_out(demos, side)
    if left.total == left.of:
        raise DemoFileError(
            path,
            f"none of its {counted(left.of, 'reach', 'reaches')} can enter the "
            "grid table: "
            f"{left.describe()}; --demos needs labelled reaches on the 16 grid "
            "points (as armplan demos synth writes)",
            no_point=left.no_point,
            no_labels=left.no_labels,
        )
    return demo_rows(demos, side), left
