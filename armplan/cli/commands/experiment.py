"""``armplan experiment``: the paper's experiments (Section V) on NAO.

    armplan experiment similarity [--out DIR] [--json] [--demos FILE.mcap ...]
        [--subjects N] [--trials N] [--points P ...] [--seed S]
        [--path human|planned] [--samples N] [--model FILE] [--mu K] [--omega W]
    armplan experiment handover [--out DIR] [--json] [--task FILE.json]
        [--movements N] [--starts chained|reference] [--model FILE]
        [--mu K] [--omega W]
    armplan experiment pace [--out DIR] [--json] [--reaches N] [--chains N]
        [--seed S] [--methods M ...] [--arm right|left] [--model FILE]
        [--mu K] [--omega W]

``similarity``: per subject and grid point, NAO's elbow (mp, least-norm,
single) against the subject's retargeted elbow over normalised time
(Fig. 14-15). Without ``--demos`` the demonstrations are the synthetic set
drawn with ``--seed`` (default 1: the shipped motion model was fitted on
seed 0, so these subjects are new to it). ``handover``: the collaboration
task, posture similarity S (eq. 22-23) to the human reference over time
(Fig. 18); each movement from where the previous one ended (``chained``,
the paper's protocol) or from the person's posture (``reference``). Both
write tables, JSON and PNG plots into ``--out`` and print the tables
(``--json``: the JSON). docs/results.md explains the protocols. ``--mu``
and ``--omega`` set the IK measures' weights (every method's); the files
then carry them in their names (``handover-chained-omega-0``). ``pace``
(not the paper's): random reaches and chains of reaches with random palms,
planned in this process; each trajectory's duration over the human one
(``--arm left``: the right arm's tasks of the seed, mirrored). Its files'
names carry the arm, the seed and the methods too when not the defaults
(``pace-left-mu-0.03-omega-0.01.json``), so that no such run replaces the
default run's ``pace.json``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import (
    add_arm,
    add_json,
    add_measure_options,
    measure_fields,
    measures_from_args,
)
from shared.errors import InvalidInputError
from shared.output_paths import try_output_folder
from shared.text.counted import counted

ORDER = 70
HELP = (
    "the paper's experiments: similarity (Fig. 14-15), handover (Fig. 18); "
    "and pace (random reaches)"
)
#: Where the results go by default.
OUT = "experiment-results"
#: The synthetic demonstration set's options and their defaults (without
#: ``--demos``; with it they do not apply). Seed 1: the shipped motion model
#: was fitted on seed 0.
SYNTHETIC: dict[str, int | None] = {
    "subjects": 16,
    "trials": 5,
    "seed": 1,
    "points": None,
}


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``experiment similarity`` and ``experiment handover``."""
    parser = commands.add_parser("experiment", help=HELP, description=HELP)
    which = parser.add_subparsers(dest="experiment", metavar="EXPERIMENT")
    which.required = True
    _similarity_parser(which)
    _handover_parser(which)
    _pace_parser(which)


def _common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", default=OUT, metavar="DIR", help=f"default {OUT}")
    parser.add_argument(
        "--model", metavar="FILE", help="motion model (default: shipped)"
    )
    add_measure_options(parser)
    add_json(parser)


def _similarity_parser(which: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    help_ = "elbow error against the subjects' retargeted elbows (Fig. 14-15)"
    parser = which.add_parser("similarity", help=help_, description=help_)
    _common(parser)
    parser.add_argument(
        "--demos", nargs="+", metavar="FILE.mcap", help="demonstrations"
    )
    parser.add_argument(
        "--subjects", type=int, help=f"synthetic subjects ({SYNTHETIC['subjects']})"
    )
    parser.add_argument(
        "--trials",
        type=int,
        help=f"synthetic trials per point ({SYNTHETIC['trials']})",
    )
    parser.add_argument(
        "--points", type=int, nargs="+", metavar="P", help="grid points (all 16)"
    )
    parser.add_argument(
        "--seed", type=int, help=f"synthetic set's seed ({SYNTHETIC['seed']})"
    )
    parser.add_argument(
        "--path",
        choices=("human", "planned"),
        default="human",
        help="NAO's wrist path: the subject's, or the planner's own (default human)",
    )
    parser.add_argument(
        "--samples", type=int, default=101, help="tau samples, 11 to 10001 (101)"
    )
    parser.add_argument(
        "--palm",
        action="store_true",
        help="NAO also turns its palm as the subject did, and each method's "
        "postures are compared with the subject's (S, eq. 22-23); a reach whose "
        "palm no posture meets is left out, and counted in a 'left out' table",
    )
    parser.set_defaults(run=run_similarity)


def _handover_parser(which: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    help_ = "posture similarity over the collaboration task (Fig. 18)"
    parser = which.add_parser("handover", help=help_, description=help_)
    _common(parser)
    parser.add_argument(
        "--task",
        metavar="FILE.json",
        help="task, without palms: NAO's are the person's (default: the demo's)",
    )
    parser.add_argument("--movements", type=int, help="only the first N movements")
    parser.add_argument(
        "--starts",
        choices=("chained", "reference"),
        default="chained",
        help="each movement from where the previous ended (default), or from "
        "the person's posture",
    )
    parser.set_defaults(run=run_handover)


#: The pace experiment's defaults that its files' names leave out.
PACE_DEFAULTS: dict[str, Any] = {
    "arm": "right",
    "seed": 5,
    "methods": ["mp", "least-norm", "single"],
}


def _pace_parser(which: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    help_ = "random reaches and chains with palms: duration over the human one"
    parser = which.add_parser("pace", help=help_, description=help_)
    _common(parser)
    parser.add_argument("--reaches", type=int, default=120, help="random reaches (120)")
    parser.add_argument(
        "--chains", type=int, default=30, help="random chains with palms (30)"
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=PACE_DEFAULTS["seed"],
        help=f"random tasks' seed ({PACE_DEFAULTS['seed']})",
    )
    parser.add_argument(
        "--methods",
        nargs="+",
        choices=("mp", "least-norm", "single"),
        default=list(PACE_DEFAULTS["methods"]),
        metavar="METHOD",
        help="mp, least-norm, single (default all)",
    )
    add_arm(
        parser,
        help="right or left, in any case (default right); left plans the "
        "mirrors of the right arm's tasks",
    )
    parser.set_defaults(run=run_pace)


def run_similarity(args: argparse.Namespace) -> int:
    """Run the similarity experiment, write and print its results."""
    from armplan.experiments.nao_reach import PathSource
    from armplan.experiments.normalised_time import tau_grid
    from armplan.experiments.similarity import Skipped
    from armplan.experiments.similarity import run_similarity as run
    from armplan.experiments.similarity_report import tables, write_report
    from armplan.experiments.similarity_summary import summary

    # every option is checked before the demonstrations are read or made
    tau_grid(args.samples)
    _output_folder(args.out)
    stages = _stages(args.model)
    measures = measures_from_args(args, stages.decider.model.measures())
    demos, source = _demos(args)
    skipped: list[Skipped] = []
    with _progress(args.json) as progress:
        task = progress.add_task("planning the reaches", total=None)
        rows = run(
            demos,
            PathSource(args.path),
            args.samples,
            stages,
            progress=lambda done, total: progress.update(
                task, completed=done, total=total
            ),
            measures=measures,
            palm=args.palm,
            skipped=skipped,
        )
    protocol = {
        "path": args.path,
        "demos": source,
        "arm": _arms(demos),
        "samples": args.samples,
        "model": _model(args),
        "measures": measures.model_dump(),
        "palm": args.palm,
        "skipped": [s._asdict() for s in skipped],
    }
    numbers = summary(rows, protocol)
    palm = "-palm" if args.palm else ""
    name = f"similarity-{args.path}{palm}{_weights(args)}"
    written = write_report(rows, numbers, args.out, name)
    _print(numbers, tables(numbers), written, args.json)
    return 0


def run_handover(args: argparse.Namespace) -> int:
    """Run the handover experiment, write and print its results."""
    from armplan.demo.task import DEFAULT_TASK, load_task
    from armplan.experiments.handover import Starts
    from armplan.experiments.handover import run_handover as run
    from armplan.experiments.handover_report import tables, write_report
    from armplan.experiments.handover_summary import summary

    task = load_task(args.task or DEFAULT_TASK)
    if args.movements is not None:
        _movements_within(args.movements, len(task.targets()))
    _output_folder(args.out)
    starts = Starts(args.starts)
    stages = _stages(args.model)
    measures = measures_from_args(args, stages.decider.model.measures())
    with _progress(args.json) as progress:
        progress.add_task("planning the task", total=None)
        reference, series = run(
            task,
            stages,
            movements=args.movements,
            starts=starts,
            measures=measures,
        )
    protocol = {
        "task": str(args.task or DEFAULT_TASK.name),
        "arm": task.arm.value,
        "movements": len(reference),
        "starts": starts.value,
        "reference": "shared.demos.reach_model, average person, retargeted to NAO",
        "model": _model(args),
        "measures": measures.model_dump(),
    }
    numbers = summary(reference, series, protocol)
    name = f"handover-{starts.value}{_weights(args)}"
    written = write_report(reference, series, numbers, args.out, name)
    _print(numbers, tables(reference, series, numbers), written, args.json)
    return 0


def run_pace(args: argparse.Namespace) -> int:
    """Run the pace experiment, write and print its results."""
    from armplan.experiments.pace import (
        CHAIN_LENGTH,
        LEAST_MOVE,
        NEAR_LIMIT,
        PaceRun,
        random_tasks,
        run_task,
    )
    from armplan.experiments.pace_report import tables, write_report
    from armplan.experiments.pace_summary import summary
    from shared.messages import Method
    from shared.robot.arm_model import load_arm

    arm = load_arm(args.arm)
    tasks = random_tasks(arm, args.reaches, args.chains, args.seed)
    _output_folder(args.out)
    stages = _stages(args.model)
    measures = measures_from_args(args, stages.decider.model.measures())
    methods = list(dict.fromkeys(args.methods))
    runs: dict[str, list[PaceRun]] = {}
    with _progress(args.json) as progress:
        bar = progress.add_task("planning", total=len(tasks) * len(methods))
        for name in methods:
            runs[name] = []
            for task in tasks:
                runs[name].append(run_task(arm, task, Method(name), stages, measures))
                progress.advance(bar)
    protocol = {
        "arm": arm.side.value,
        "seed": args.seed,
        "reaches": args.reaches,
        "chains": args.chains,
        "chain_length": CHAIN_LENGTH,
        "least_move_m": LEAST_MOVE,
        "near_limit_rad": NEAR_LIMIT,
        "model": _model(args),
        "measures": measures.model_dump(),
    }
    numbers = summary(runs, protocol)
    written = write_report(numbers, args.out, _pace_name(args, methods))
    _print(numbers, tables(numbers), written, args.json)
    return 0


def _pace_name(args: argparse.Namespace, methods: list[str]) -> str:
    """The pace files' name: ``pace``, then what differs from the defaults.

    The arm, the seed, the methods and the weights, each only if given
    otherwise than by default (``pace-left-seed-7-mp-mu-0.03-omega-0.01``),
    so that such a run never replaces the default run's files.
    """
    from shared.robot.side import Side

    side = Side.parse(args.arm).value
    arm = "" if side == PACE_DEFAULTS["arm"] else f"-{side}"
    seed = "" if args.seed == PACE_DEFAULTS["seed"] else f"-seed-{args.seed}"
    chosen = "" if methods == PACE_DEFAULTS["methods"] else "-" + "-".join(methods)
    return f"pace{arm}{seed}{chosen}{_weights(args)}"


def _demos(args: argparse.Namespace) -> tuple[Any, str]:
    """The demonstrations and where they came from."""
    from shared.demos import read_demos, synthesize

    given = [name for name in SYNTHETIC if getattr(args, name) is not None]
    if args.demos:
        if given:
            raise InvalidInputError(
                f"--{given[0]} is an option of the synthetic demonstrations; "
                "with --demos the files' subjects, trials and points are used",
                field=given[0],
            )
        return read_demos(args.demos), ", ".join(args.demos)
    for name, default in SYNTHETIC.items():
        if getattr(args, name) is None:
            setattr(args, name, default)
    points = tuple(sorted(set(args.points))) if args.points else None
    demos = synthesize(
        args.seed, subjects=args.subjects, trials=args.trials, points=points
    )
    return (
        demos,
        f"synthetic, seed {args.seed}, {counted(args.subjects, 'subject')}, "
        f"{counted(args.trials, 'trial')}",
    )


def _arms(demos: Any) -> str:
    """The arms the demonstrations move: ``"right"``, ``"left"`` or both."""
    from shared.robot.side import Side

    arms = {trial.arm for trial in demos.trials}
    return ", ".join(side.value for side in Side if side in arms)


def _model(args: argparse.Namespace) -> str:
    """The motion model, for the protocol: the file as given, or ``"shipped"``."""
    return str(args.model) if args.model else "shipped"


def _weights(args: argparse.Namespace) -> str:
    """The weights given, for file names: ``"-omega-0"``, or ``""`` if none."""
    return "".join(f"-{name}-{value:g}" for name, value in measure_fields(args).items())


def _movements_within(value: int, count: int) -> None:
    _at_least(value, 1, "movements")
    if value > count:
        raise InvalidInputError(
            f"--movements {value}: the task has {count} movements", field="movements"
        )


def _at_least(value: int, low: int, name: str) -> None:
    if value < low:
        raise InvalidInputError(
            f"--{name} must be at least {low}, got {value}", field=name
        )


def _output_folder(out: str) -> None:
    """Check that ``--out`` can be made and written, before any work.

    Making it finds what checking alone cannot foresee (``/proc``, ``/sys``):
    such a folder used to fail once every reach was planned, in other words
    ("cannot make the output directory ...: [Errno 2] ..."). The folder is
    made for good only when the results are written.

    Raises:
        InvalidInputError: naming ``--out``, the folder and why.
    """
    try_output_folder(out)


def _stages(model: str | None) -> Any:
    """The planner's stages in this process, with ``model`` if given.

    Raises:
        ModelFileError: naming the file: unreadable, or a model the decision
            cannot use (``services.fit.decidable``).
    """
    from services.fit.decidable import load_decidable
    from services.planner.stages import LocalStages

    return LocalStages(load_decidable(model) if model else None)


def _print(
    numbers: dict[str, Any], tables: dict[str, Any], written: list[Any], as_json: bool
) -> None:
    if as_json:
        print_json({**numbers, "files": [str(p) for p in written]})
        return
    for title, (headers, rows) in tables.items():
        sys.stdout.write(f"\n{title}\n")
        print_table(headers, rows)
    if "bars" in numbers:
        sys.stdout.write("\nbars: " + _bars(numbers["bars"]) + "\n")
    sys.stdout.write("wrote " + ", ".join(str(p) for p in written) + "\n")


def _bars(bars: dict[str, Any]) -> str:
    return "; ".join(
        f"{name} {'met' if bar['met'] else 'NOT met'}" for name, bar in bars.items()
    )


@contextmanager
def _progress(quiet: bool) -> Iterator[Any]:
    """The progress bar on stderr (off with --json)."""
    from armplan.cli.progress import progress_bar

    with progress_bar(quiet) as progress:
        yield progress
