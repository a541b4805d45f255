"""``armplan demos``: make, import and summarise demonstration files (MCAP).

    armplan demos synth -o FILE.mcap [--seed N] [--subjects N] [--trials N]
    armplan demos import FILE.c3d|FILE.csv ... --markers MAP.json -o FILE.mcap
        [--first-trial N] [--allow-long]
    armplan demos info FILE.mcap ... [--json]

``synth`` writes the synthetic set (the paper's protocol, ``shared.demos``);
``import`` reads C3D or CSV motion capture with a marker map (format in
``shared/demos/markers.py``, CSV columns in ``shared/demos/csv_import.py``;
CSV times in seconds, milliseconds refused), retargets it to NAO and writes
the same MCAP form; ``info`` counts subjects, trials, samples and labels.

Files are checked before any work: a file given twice (its trials would
count twice) and an output that is also an input are refused; so is a
trial whose samples another file's trial has (a copy). ``import`` numbers
the trials from ``--first-trial`` (default 0) across its files (a CSV
trial's errors and notes name its number in the file), refuses a
trial that is no reach (its wrist ends near its start, or moves for under
0.1 s) and one that is more than one reach (mostly still, over 10 s, or
its wrist stopping on its way; ``shared/demos/reach_span.py``) unless
``--allow-long`` (a CSV trial's refusals name its lines), and notes on stderr
how many frames it filled where a marker was missing (a gap at a trial's
end, or over 0.1 s, is refused: ``shared/demos/marker_gaps.py``) and a goal
NAO cannot reach (``shared/demos/goal_reach.py``).
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from pathlib import Path
from typing import TYPE_CHECKING

from armplan.cli.output import apart_from, print_json, print_table
from armplan.cli.parsing import add_json
from shared.errors import DemoFileError, InvalidInputError
from shared.text.counted import counted

if TYPE_CHECKING:
    from shared.demos import Subject, Trial

ORDER = 30
HELP = "demonstrations: synthesise, import motion capture (C3D, CSV), summarise"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``demos`` and its subcommands."""
    parser = commands.add_parser("demos", help=HELP, description=HELP)
    actions = parser.add_subparsers(
        dest="action", metavar="ACTION", parser_class=type(parser)
    )
    actions.required = True
    synth = actions.add_parser(
        "synth",
        help="write the synthetic demonstration set",
        description="16 subjects x 16 grid points x 5 trials at 100 Hz, "
        "retargeted to NAO (the paper's protocol)",
    )
    synth.add_argument(
        "-o", "--output", required=True, metavar="FILE.mcap", help="file to write"
    )
    synth.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    synth.add_argument("--subjects", type=int, default=16, help="default 16")
    synth.add_argument("--trials", type=int, default=5, help="per point, default 5")
    synth.set_defaults(run=run_synth)
    imported = actions.add_parser(
        "import",
        help="import C3D or CSV motion capture",
        description="read C3D (one trial per file) or CSV files (times in "
        "seconds, or ms if the marker map says so), retarget to NAO",
    )
    imported.add_argument(
        "files", nargs="+", metavar="FILE.c3d|FILE.csv", help="motion capture"
    )
    imported.add_argument(
        "--markers",
        required=True,
        metavar="MAP.json",
        help="which markers are shoulder, elbow, wrist (and thumb); the arm, "
        "units, time units and axes (docs/decision.md)",
    )
    imported.add_argument(
        "-o", "--output", required=True, metavar="FILE.mcap", help="file to write"
    )
    imported.add_argument(
        "--first-trial",
        type=_whole,
        default=0,
        metavar="N",
        help="number the trials from N (default 0): files imported apart and "
        "fitted together need distinct numbers for one subject",
    )
    imported.add_argument(
        "--allow-long",
        action="store_true",
        help="import a trial that is mostly still, over 10 s or stops on its "
        "way anyway (a note on stderr); by default it is refused: a trial must "
        "be one reach",
    )
    imported.set_defaults(run=run_import)
    info = actions.add_parser("info", help="summarise demonstration files")
    info.add_argument(
        "files", nargs="+", metavar="FILE.mcap", help="demonstration files"
    )
    add_json(info)
    info.set_defaults(run=run_info)


def run_synth(args: argparse.Namespace) -> int:
    """Write the synthetic set (the summary apart from it: ``apart_from``)."""
    with apart_from(args.output):
        return _synth(args)


def _synth(args: argparse.Namespace) -> int:
    """Write the synthetic set; its summary on stdout."""
    from shared.demos import synthesize, write_demos
    from shared.demos.demo_file import SYNTHETIC
    from shared.output_paths import check_output_file

    check_output_file(args.output)
    demos = synthesize(args.seed, subjects=args.subjects, trials=args.trials)
    count = write_demos(args.output, demos, source=f"{SYNTHETIC}{args.seed}")
    sys.stdout.write(
        f"{args.output}: {counted(len(demos.subjects), 'subject')}, "
        f"{counted(len(demos.trials), 'trial')}, {count} samples (seed {args.seed})\n"
    )
    return 0


def run_import(args: argparse.Namespace) -> int:
    """Read motion capture, retarget, write MCAP (the summary apart from it)."""
    with apart_from(args.output):
        return _import(args)


def _import(args: argparse.Namespace) -> int:
    """Read motion capture, retarget, write MCAP; the summary on stdout."""
    from shared.demos import DemoSet, write_demos
    from shared.demos.c3d_import import read_c3d
    from shared.demos.csv_import import read_csv
    from shared.demos.marker_side import other_side_named
    from shared.demos.markers import read_marker_map
    from shared.demos.paths import check_distinct
    from shared.demos.repeats import Register
    from shared.output_paths import check_output_file

    check_distinct(args.files)
    check_output_file(args.output, [*args.files, args.markers])
    for name in args.files:
        _check_capture_name(Path(name))
    markers = read_marker_map(args.markers)
    named = other_side_named(markers.names, markers.arm)
    if named is not None:  # the map gives its arm: taken at its word
        _note(
            f'{args.markers}: {named}, but the map\'s "arm" is '
            f"{markers.arm.value}: retargeted to NAO's {markers.arm.value} arm, "
            "as the map says"
        )
    for name in args.files:  # a name too long for a subject, before any work
        markers.subject_of(Path(name))
    subjects: dict[str, Subject] = {}
    trials: list[Trial] = []
    register = Register()
    for name in args.files:
        path = Path(name)
        base = _next_trial(trials, args.first_trial)
        if path.suffix.lower() == ".c3d":
            trial, subject = read_c3d(path, markers, base, report=_note)
            found = [trial]
        else:
            found, subject = read_csv(path, markers, report=_note)
        for trial in found:  # by the file's own numbers, as its gap notes are
            _check_one_reach(trial, name, args.allow_long)
        if path.suffix.lower() == ".csv":
            found = [t._replace(trial=base + i) for i, t in enumerate(found)]
        _check_one_person(subjects.get(subject.name), subject, name)
        subjects.setdefault(subject.name, subject)
        for trial in found:
            register.add(trial, name)
        trials.extend(found)
    count = write_demos(
        args.output, DemoSet(subjects, trials), source=", ".join(args.files)
    )
    sys.stdout.write(
        f"{args.output}: {counted(len(subjects), 'subject')}, "
        f"{counted(len(trials), 'trial')}, "
        f"{count} samples, retargeted to NAO's {markers.arm.value} arm\n"
    )
    return 0


def _check_capture_name(path: Path) -> None:
    """Refuse a path that is no .c3d or .csv file, naming what it is.

    A folder of captures was "expected a .c3d or .csv file", which did not
    say that the files in it are what to give.

    Raises:
        InvalidInputError: (field ``files``) naming the path.
    """
    if path.is_dir():
        raise InvalidInputError(
            f"{path}: a folder, not a capture file: give the files in it "
            f"(e.g. {path / '*.c3d'} or {path / '*.csv'})",
            field="files",
        )
    from shared.demos.demo_file import CAPTURE_SUFFIXES

    if path.suffix.lower() not in CAPTURE_SUFFIXES:
        raise InvalidInputError(f"{path}: expected a .c3d or .csv file", field="files")


def _check_one_reach(trial: Trial, name: str, allow: bool) -> None:
    """Refuse a trial that is no reach, or (unless ``allow``) more than one.

    Raises:
        DemoFileError: naming the file, subject, trial (and for a CSV its
            lines, in the evidence too), its length and its wrist's travel,
            moving time or stillness.
    """
    from shared.demos.reach_span import long_trial_problem, not_a_reach_problem
    from shared.demos.sample_lines import line_evidence

    lines = line_evidence(trial.lines, 0, len(trial.times) - 1)
    problem = not_a_reach_problem(trial)
    if problem is not None:
        raise DemoFileError(
            name,
            f"{problem}. A trial must be one reach, from its start to its goal: "
            "leave this one out",
            trial=trial.trial,
            subject=trial.subject,
            **lines,
        )
    problem = long_trial_problem(trial)
    if problem is None:
        return
    if allow:
        _note(f"{name}: {problem}; imported as it is (--allow-long)")
        return
    raise DemoFileError(
        name,
        f"{problem}. Crop it to the reach, or give --allow-long to import it as it is",
        trial=trial.trial,
        subject=trial.subject,
        **lines,
    )


def _note(text: str) -> None:
    """A note for the user on stderr (not an error: the import goes on)."""
    sys.stderr.write(f"armplan: note: {text}\n")


def _check_one_person(seen: Subject | None, subject: Subject, name: str) -> None:
    """Raise if ``subject`` (from file ``name``) is another person of that name.

    Two people's ``reach.csv`` from two folders, with no subject in the
    marker map, both became subject ``reach``: one person of two arms. One
    person's arm, measured in two files, agrees within ``SAME_ARM``
    (``shared.demos.same_person``, which ``armplan fit`` applies too).

    Raises:
        DemoFileError: naming the file, the subject and both arms.
    """
    from shared.demos.same_person import SAME_ARM, same_arm

    if seen is None or same_arm(seen, subject):
        return
    raise DemoFileError(
        name,
        f"subject {subject.name!r} measures {subject.upper_arm:.3f} + "
        f"{subject.forearm:.3f} m here, {seen.upper_arm:.3f} + "
        f"{seen.forearm:.3f} m in an earlier file, more than {SAME_ARM:.0%} "
        "apart: two people under one name? Give each file's person a name (the "
        'marker map\'s "subject")',
    )


def _next_trial(trials: list[Trial], first: int) -> int:
    """The next free trial number from ``first`` (numbered across files)."""
    return max((t.trial + 1 for t in trials), default=first)


def _whole(text: str) -> int:
    """A trial number: a whole number >= 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {value}")
    return value


def run_info(args: argparse.Namespace) -> int:
    """Summarise demonstration files."""
    from shared.demos import read_demos

    demos = read_demos(args.files)
    labels = Counter(
        label
        for t in demos.trials
        for label in (t.labels or ["(unlabelled)"] * len(t.times))
    )
    summary = {
        "files": args.files,
        "subjects": sorted(demos.subjects),
        "trials": len(demos.trials),
        "samples": demos.samples,
        "labels": dict(labels.most_common()),
    }
    if args.json:
        print_json(summary)
        return 0
    sys.stdout.write(
        f"{counted(len(demos.subjects), 'subject')}, "
        f"{counted(len(demos.trials), 'trial')}, "
        f"{demos.samples} samples\n"
    )
    print_table(("primitive label", "samples"), labels.most_common())
    return 0
