"""Entry point of the ``armplan`` command.

This module imports only the standard library and the CLI's own light
modules: the commands, and the ``shared`` package (which loads libqi), load
inside :func:`main` with Ctrl-C held (see :mod:`armplan.cli.held_interrupt`).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import pkgutil
import signal
import sys
from collections.abc import Callable, Sequence
from types import ModuleType

from armplan import __version__
from armplan.cli import commands as commands_package
from armplan.cli.held_interrupt import held_interrupt
from armplan.cli.stdout_guard import StdoutError, discard_stdout, guarded_stdout
from armplan.cli.termination import (
    HUNG_UP_CODE,
    INTERRUPTED_CODE,
    TERMINATED_CODE,
    signal_of,
    stopped_by,
    stops_unwinding,
)


def command_modules() -> list[ModuleType]:
    """Every module of ``armplan.cli.commands``, in help order."""
    modules = [
        importlib.import_module(f"{commands_package.__name__}.{info.name}")
        for info in pkgutil.iter_modules(commands_package.__path__)
        if not info.name.startswith("_")
    ]
    return sorted(modules, key=lambda m: (getattr(m, "ORDER", 100), m.__name__))


def build_parser() -> argparse.ArgumentParser:
    """The parser with every command registered."""
    from shared.command_line import ArgumentParser

    parser = ArgumentParser(
        prog="armplan", description="Human-like arm movements for the NAO robot."
    )
    parser.add_argument("--version", action="version", version=f"armplan {__version__}")
    commands = parser.add_subparsers(
        dest="command", metavar="COMMAND", parser_class=ArgumentParser
    )
    commands.required = True
    for module in command_modules():
        module.add_parser(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run one command; returns the exit code.

    0 ok, 1 armplan error, 2 usage, 130 Ctrl-C, 143 SIGTERM, 129 SIGHUP
    (every command unwinds on SIGTERM and SIGHUP as on Ctrl-C; the commands
    that record or serve until stopped exit 0 on each). Ctrl-C, SIGTERM or
    SIGHUP while the commands load exits so once they have loaded, without
    a traceback.
    """
    with held_interrupt() as held:
        parser = build_parser()
        args = parser.parse_args(argv)
    if held.signal is not None:
        return _stopped(held.signal)
    from shared.offered_options import offering

    with offering(chosen_options(parser, args)):  # for the hints of its errors
        return run_command(args.run, args)


def chosen_options(
    parser: argparse.ArgumentParser, args: argparse.Namespace
) -> set[str]:
    """The option strings of the command ``args`` chose (``--config``, ...).

    Those of ``parser`` and of each subcommand parser on the way to it.
    """
    options: set[str] = set()
    for action in parser._actions:
        options.update(action.option_strings)
        if isinstance(action, argparse._SubParsersAction):
            chosen = action.choices.get(getattr(args, action.dest, None) or "")
            if chosen is not None:
                options |= chosen_options(chosen, args)
    return options


def run_command(
    run: Callable[[argparse.Namespace], int], args: argparse.Namespace
) -> int:
    """``run(args)``'s exit code, with errors and signals reported on stderr.

    Every command unwinds on SIGTERM and SIGHUP as on Ctrl-C
    (:func:`~armplan.cli.termination.stops_unwinding`: a signal that comes
    as its handlers are set or put back is reported too, not raised out of
    here). An error raised after SIGTERM or Ctrl-C arrived is reported as
    that signal: it is how the signal's exception came out (see
    :mod:`armplan.cli.termination`), not a failure of the command.
    """
    from armplan.cli.output import report_error
    from shared.errors import ArmplanError

    try:
        with stops_unwinding(), guarded_stdout():
            code = int(run(args))
            sys.stdout.flush()  # a buffered write fails here, not at exit
    except KeyboardInterrupt as stop:  # Terminated, HungUp: SIGTERM, SIGHUP (demo)
        return _stopped(stopped_by() or signal_of(stop))
    except ArmplanError as error:
        if (signum := stopped_by()) is not None:
            return _stopped(signum)
        return report_error(error, getattr(args, "json", False))
    except StdoutError as error:  # e.g. `> /dev/full`, or stdout closed
        if (signum := stopped_by()) is not None:
            return _stopped(signum)
        return _unwritten(error)
    except BrokenPipeError:  # e.g. `armplan ... | head`: the reader left
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error at exit
        return 0
    except Exception:
        if (signum := stopped_by()) is not None:
            return _stopped(signum)
        raise
    signum = stopped_by()
    return code if signum is None else _stopped(signum)


def _unwritten(error: StdoutError) -> int:
    """Say that the output could not be written (if stderr works); exit code 1."""
    if sys.stdout is None or sys.stdout is sys.__stdout__:
        discard_stdout()  # what it holds: exit's flush would fail again
    with contextlib.suppress(OSError, AttributeError):
        sys.stderr.write(f"armplan: error: cannot write the output: {error.strerror}\n")
        sys.stderr.flush()
    return 1


#: What each stop signal is called, and its exit code.
_STOPPED = {
    signal.SIGTERM: ("terminated", TERMINATED_CODE),
    signal.SIGHUP: ("hung up", HUNG_UP_CODE),
    signal.SIGINT: ("interrupted", INTERRUPTED_CODE),
}


def _stopped(signum: signal.Signals) -> int:
    """Say which signal stopped the command; its exit code (143, 129 or 130).

    After a hangup the terminal may be gone (a write fails with EIO): the
    exit code still says it.
    """
    said, code = _STOPPED.get(signum, _STOPPED[signal.SIGINT])
    with contextlib.suppress(OSError):
        sys.stderr.write(f"armplan: {said}\n")
        sys.stderr.flush()
    return code


if __name__ == "__main__":
    raise SystemExit(main())
