"""``armplan fit``: fit the motion model to demonstration files.

    armplan fit DEMOS.mcap ... -o model.json [--bins 20] [--smoothing 1]
                [--hold-out N] [--json]

Shows its progress, then prints each motion variable's fitted exponential
rate with its log-likelihood and leave-one-out cross-validated
log-likelihood, the primitives the network learned, and the IK measures'
weights mu and omega fitted on the same postures (``services.fit.weights``),
which the model carries to the IK. With ``--hold-out
N`` the last N subjects (by name) are left out of the fit and the decision
is compared with their labels sample by sample: the agreement and the
confusion matrix are printed, and the model written is the one fitted
without them.

A model the decision cannot use (tables holding a probability that rounds
to 0, as a smoothing of 5e-324 gives) is refused before it is written
(``services.fit.decidable``): nothing is written and the exit status is 1,
so no ``--model`` file is made that every command would refuse.

The output is checked before any work: it must be a file name in an
existing folder and none of the demonstration files (which it would
overwrite); a demonstration file given twice is refused (its trials would
count twice).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from armplan.cli.output import print_json
from armplan.cli.parsing import add_json
from shared.errors import InvalidInputError

ORDER = 40
HELP = "fit the motion model (densities and network) to demonstrations"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``fit``."""
    parser = commands.add_parser("fit", help=HELP, description=HELP)
    parser.add_argument(
        "files", nargs="+", metavar="DEMOS.mcap", help="demonstration files"
    )
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="model.json",
        help="the motion model to write",
    )
    parser.add_argument(
        "--bins", type=int, default=20, help="states per variable (default 20)"
    )
    parser.add_argument(
        "--smoothing",
        type=float,
        default=1.0,
        help="pseudo-count per table cell (default 1)",
    )
    parser.add_argument(
        "--hold-out",
        type=int,
        default=0,
        metavar="N",
        help="leave the last N subjects out and report the decision's agreement",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Read, fit, write, report."""
    from services.fit import fit_model, save_model
    from shared.demos import read_demos
    from shared.demos.paths import check_distinct
    from shared.output_paths import check_output_file

    check_distinct(args.files)
    check_output_file(args.output, args.files)
    with _progress(args.json) as (progress, console):
        task = progress.add_task("reading demonstrations", total=None)
        demos = read_demos(args.files)
        names = sorted(demos.subjects)
        train, held = _split(names, args.hold_out)
        fitted = demos.only(set(train))
        progress.update(task, description="variables, then weights", total=None)
        model = fit_model(
            fitted,
            bins=args.bins,
            smoothing=args.smoothing,
            sources=args.files,
            progress=lambda done, total: progress.update(
                task, completed=done, total=total
            ),
        )
        _check_decidable(model, args)
        save_model(model, args.output)
        agreement = None
        if held:
            progress.update(task, description="deciding on held-out subjects")
            from services.decide.agreement import agreement as compare

            agreement = compare(model, demos.only(set(held)))
    report = _report(model, args.output, held, agreement)
    if args.json:
        print_json(report)
    else:
        _print(console, model, args.output, held, agreement)
    return 0


def _check_decidable(model: Any, args: argparse.Namespace) -> None:
    """Refuse ``model`` if the decision cannot use it, before it is written.

    Raises:
        InvalidInputError: (field ``smoothing``) naming the output, the fit's
            bins and smoothing, and the table that cannot decide.
    """
    from services.fit.decidable import check_decidable

    try:
        check_decidable(model)
    except InvalidInputError as error:
        raise InvalidInputError(
            f"the model fitted (bins {args.bins}, smoothing {args.smoothing!r}) "
            f"is not written to {args.output}: {error.message}",
            field="smoothing",
            table=error.evidence.get("table"),
        ) from None


def _split(names: list[str], hold_out: int) -> tuple[list[str], list[str]]:
    if not 0 <= hold_out < len(names):
        raise InvalidInputError(
            f"--hold-out must be 0..{len(names) - 1} ({len(names)} subjects), "
            f"got {hold_out}",
            field="hold_out",
        )
    cut = len(names) - hold_out
    return names[:cut], names[cut:]


@contextmanager
def _progress(quiet: bool) -> Iterator[tuple[Any, Any]]:
    """The progress bar on stderr, and a console for stdout."""
    from armplan.cli.console import StdoutConsole
    from armplan.cli.progress import progress_bar

    with progress_bar(quiet) as progress:
        yield progress, StdoutConsole(file=sys.stdout, soft_wrap=True)


def _report(model: Any, output: str, held: list[str], agreement: Any) -> dict[str, Any]:
    from services.decide.decider import CANDIDATES
    from services.fit.network import describe

    report: dict[str, Any] = {
        "model": output,
        "network": describe(),
        "samples": model.samples,
        "subjects": model.subjects,
        "primitives": model.primitives,
        "variables": [
            {
                "name": v.name,
                "unit": v.unit,
                "rate": v.rate,
                "mean": 1.0 / v.rate,
                "samples": v.samples,
                "log_likelihood": v.log_likelihood,
                "loo_log_likelihood": v.loo_log_likelihood,
            }
            for v in model.variables
        ],
        "weights": None if model.weights is None else model.weights.model_dump(),
    }
    if agreement is not None:
        report["held_out"] = {
            "subjects": held,
            "samples": agreement.samples,
            "agreement": agreement.fraction,
            "decided": list(CANDIDATES),
            "confusion": {label: counts for label, counts in agreement.rows()},
        }
    return report


def _print(
    console: Any, model: Any, output: str, held: list[str], agreement: Any
) -> None:
    from rich.table import Table

    table = Table(title=f"exponential densities ({model.samples} samples)")
    for column in (
        "variable",
        "rate",
        "rate unit",
        "mean",
        "log-lik.",
        "LOO CV log-lik.",
    ):
        table.add_column(column, justify="left" if column == "variable" else "right")
    for v in model.variables:
        table.add_row(
            v.name,
            f"{v.rate:.4f}",
            f"1/{v.unit}" if v.unit == "rad" else "1/arm length",
            f"{1.0 / v.rate:.4f}",
            "-" if v.log_likelihood is None else f"{v.log_likelihood:.4f}",
            "-" if v.loo_log_likelihood is None else f"{v.loo_log_likelihood:.4f}",
        )
    console.print(table)
    from services.fit.network import describe

    console.print("network arrows: " + "; ".join(describe()))
    console.print(
        f"network: {len(model.primitives)} primitives "
        f"({', '.join(model.primitives)}), {model.bins} states per variable; "
        f"fitted on {len(model.subjects)} subjects; written to {output}"
    )
    console.print(_weights_line(model.weights))
    if agreement is not None:
        _print_agreement(console, held, agreement)


def _weights_line(weights: Any) -> str:
    """The fitted measures' weights in one line."""
    if weights is None:
        return (
            "measures' weights: not fitted, no posture away from NAO's joint "
            "limits (the IK uses the shipped ones)"
        )
    omega = (
        "omega not fitted (no wrist roll in the demonstrations)"
        if weights.omega is None
        else f"omega = {weights.omega:g} J/rad^2"
    )
    line = (
        f"measures' weights: mu = {weights.mu:g} J/rad^2, {omega}; "
        f"{weights.samples} equations, {100 * weights.explained:.1f} % of the "
        "gravity term explained"
    )
    return line if weights.trusted else f"{line}; {weights.untrusted()}"


def _print_agreement(console: Any, held: list[str], agreement: Any) -> None:
    from rich.table import Table

    from services.decide.decider import CANDIDATES

    console.print(
        f"held-out subjects {', '.join(held)}: the decision agrees with the labels "
        f"on {agreement.agreed} of {agreement.samples} samples "
        f"({100 * agreement.fraction:.1f} %)"
    )
    table = Table(title="confusion matrix (rows: labels, columns: decisions)")
    table.add_column("label \\ decided")
    used = [i for i in range(len(CANDIDATES)) if agreement.confusion[:, i].sum() > 0]
    for i in used:
        table.add_column(CANDIDATES[i], justify="right")
    for label, counts in agreement.rows():
        table.add_row(label, *(str(counts[i]) for i in used))
    console.print(table)
