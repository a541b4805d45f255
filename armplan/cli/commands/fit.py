"""``armplan fit``: fit the motion model to demonstration files.

    armplan fit DEMOS.mcap ... -o model.json [--bins 20] [--smoothing 1]
                [--hold-out N] [--json]
    armplan fit DEMOS.mcap ... --remote [--connect E] [--zenoh-config F]
                [--timeout S] [--bins 20] [--smoothing 1] [--json]
    armplan fit --show --remote [--connect E] [--zenoh-config F] [--json]

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

With ``--remote`` (or ``--connect`` / ``--zenoh-config``) the running fit
service fits (``<ns>/fit``): it reads the files by the names given, inside
its own demonstration directory (its ``$ARMPLAN_DEMOS_DIR``, else its
working directory), serves the model and publishes it to the decide
service; the command prints the served model's digest (the one the
service logs) and the files it was fitted on. It waits ``--timeout`` seconds
(default ``REMOTE_TIMEOUT``): a fit of a large set takes a while, and one
whose caller stopped waiting is not served; nor is one whose command was
interrupted or killed (its session ended). ``--show --remote`` prints the
model the service serves now.

The options and the output are checked before any work: ``--bins`` 2..64,
``--smoothing`` in (0, 1e6], ``--timeout`` a positive number of seconds (up
to a day); the output must be a file name in an existing folder and none of
the demonstration files (which it would overwrite); a demonstration file
given twice is refused (its trials would count twice).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from armplan.cli.output import apart_from, print_json
from armplan.cli.parsing import add_json
from armplan.cli.remote import add_remote, check_timeout, is_remote
from shared.errors import InvalidInputError, RequestTimeoutError
from shared.text.counted import counted

ORDER = 40
#: How long ``--remote`` waits for the fit service's fit by default [s].
REMOTE_TIMEOUT = 600.0
HELP = "fit the motion model (densities and network) to demonstrations"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``fit``."""
    parser = commands.add_parser("fit", help=HELP, description=HELP)
    parser.add_argument(
        "files",
        nargs="*",
        metavar="DEMOS.mcap",
        help="demonstration files (with --remote: names inside the fit "
        "service's demonstration directory)",
    )
    parser.add_argument(
        "-o",
        "--output",
        metavar="model.json",
        help="the motion model to write (required unless --remote)",
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
    add_remote(parser)
    parser.add_argument(
        "--timeout",
        type=float,
        metavar="S",
        help=f"with --remote: longest wait for the fit [s] (default "
        f"{REMOTE_TIMEOUT:g})",
    )
    parser.add_argument(
        "--show",
        action="store_true",
        help="with --remote: show the model the fit service serves, fit nothing",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Read, fit, write, report; or have the fit service fit, or show its model."""
    _check_options(args)
    if is_remote(args):
        return _run_remote(args)
    with apart_from(args.output):  # -o /dev/stdout: the model alone there
        return _run_local(args)


def _run_local(args: argparse.Namespace) -> int:
    """Read, fit, write the model to ``args.output``, report."""
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


def _check_options(args: argparse.Namespace) -> None:
    """Refuse an option out of range, ignored by the form chosen, or missing.

    ``--bins``, ``--smoothing`` and ``--timeout`` are checked before any
    demonstration is read or any router is asked; each error names the option.
    """
    from services.fit.fitting import check_options
    from shared.messages.fit_request import MAX_FILES

    check_options(args.bins, args.smoothing)
    _check_form(args)
    check_timeout(args.timeout)
    if is_remote(args) and len(args.files) > MAX_FILES:
        raise InvalidInputError(
            f"the fit service reads at most {MAX_FILES} files in one fit, "
            f"got {len(args.files)}",
            field="files",
        )


def _check_form(args: argparse.Namespace) -> None:
    """Refuse options the chosen form would ignore, or a missing one, naming it."""
    if is_remote(args):
        for name, why in (
            ("output", "the fit service serves the model and keeps it itself"),
            ("hold_out", "the fit service fits on every subject"),
        ):
            if getattr(args, name):
                raise InvalidInputError(
                    f"--{name.replace('_', '-')} does not go with --remote: {why}",
                    field=name,
                )
        if args.show and args.files:
            raise InvalidInputError(
                "--show fits nothing: give demonstration files or --show",
                field="files",
            )
        if not args.show and not args.files:
            raise InvalidInputError(
                "give the demonstration files for the fit service to fit, or "
                "--show for the model it serves",
                field="files",
            )
        return
    for name in ("show", "timeout"):
        if getattr(args, name) not in (None, False):
            raise InvalidInputError(
                f"--{name} goes with --remote (the running fit service)", field=name
            )
    if not args.files:
        raise InvalidInputError("give the demonstration files to fit", field="files")
    if args.output is None:
        raise InvalidInputError(
            "give -o model.json, the motion model to write (or --remote, for "
            "the running fit service to fit and serve it)",
            field="output",
        )


def _run_remote(args: argparse.Namespace) -> int:
    """Have the fit service fit ``args.files`` (or show its model); report it."""
    from armplan.cli.remote import connect
    from shared.bus import NoArguments
    from shared.bus.routes import FIT, FIT_MODEL
    from shared.messages import FitRequest

    with connect(args) as bus:
        if args.show:
            model = bus.call(FIT_MODEL, NoArguments())
        else:
            request = FitRequest(
                files=args.files, bins=args.bins, smoothing=args.smoothing
            )
            timeout = REMOTE_TIMEOUT if args.timeout is None else args.timeout
            try:
                # repeat: a query that ended reaching no one (Zenoh's empty
                # route just after a session starts) is asked again; one
                # asked again while the fit runs joins it (its call id)
                model = bus.call(FIT, request, timeout=timeout, repeat=True)
            except KeyboardInterrupt:  # Ctrl-C, SIGTERM, SIGHUP
                _say_fit_abandoned()
                raise
            except InvalidInputError as error:
                raise _where_files_are(error) from None
            except RequestTimeoutError as error:
                error.message += (
                    "; the fit service stops a fit whose caller stopped waiting "
                    "and serves nothing from it: give a longer --timeout"
                )
                raise
    _print_served(model, args.json, fitted=not args.show)
    return 0


def _say_fit_abandoned() -> None:
    """Say what becomes of a remote fit whose command was interrupted.

    The fit service sees this command's session end (its caller token goes)
    and abandons the fit at its next step, serving nothing from it. It used
    to go on and serve the model minutes later, and the command said so: a
    lab that pressed Ctrl-C had taken the fit as cancelled.
    """
    sys.stderr.write(
        "armplan: warning: the fit service abandons this fit once it sees "
        "this command's session end (at its next step) and serves nothing "
        "from it: the model it served stays; 'armplan fit --show --remote' "
        "says which model it serves\n"
    )


def _where_files_are(error: InvalidInputError) -> InvalidInputError:
    """``error``, told how the fit service finds files if it refused a name."""
    if error.evidence.get("field") != "files" or "outside" not in error.message:
        return error
    return InvalidInputError(
        f"{error.message}. With --remote the names are sent as given and the "
        "fit service reads them inside its own demonstration directory "
        "($ARMPLAN_DEMOS_DIR where it runs, else its working directory), not "
        "this machine's folders: give names relative to that directory (e.g. "
        "a.mcap), or copy the files there",
        field="files",
    )


def _print_served(model: Any, json: bool, *, fitted: bool) -> None:
    """The served model: its digest, samples, sources, subjects, primitives."""
    from services.fit.model_state import digest

    if json:
        print_json(
            {
                "digest": digest(model),
                "fitted": fitted,
                "sources": model.sources,
                "samples": model.samples,
                "subjects": model.subjects,
                "primitives": model.primitives,
                "bins": model.bins,
                "smoothing": model.smoothing,
            }
        )
        return
    what = "fitted and serving" if fitted else "serving"
    sys.stdout.write(
        f"{what} model {digest(model)}: {model.samples} samples of "
        f"{', '.join(model.sources) or 'no named file'} "
        f"({counted(len(model.subjects), 'subject')}; primitives "
        f"{', '.join(model.primitives)}; {model.bins} states per variable)\n"
    )


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
            f"--hold-out must be 0..{len(names) - 1} "
            f"({counted(len(names), 'subject')}), "
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
        f"network: {counted(len(model.primitives), 'primitive')} "
        f"({', '.join(model.primitives)}), {model.bins} states per variable; "
        f"fitted on {counted(len(model.subjects), 'subject')}; written to {output}"
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
