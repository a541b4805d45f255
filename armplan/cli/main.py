"""Entry point of the ``armplan`` command."""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import sys
from collections.abc import Sequence
from types import ModuleType

from armplan import __version__
from armplan.cli import commands as commands_package
from armplan.cli.output import report_error
from armplan.cli.parsing import ArgumentParser
from armplan.cli.termination import INTERRUPTED_CODE, TERMINATED_CODE, Terminated
from shared.errors import ArmplanError


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

    0 ok, 1 armplan error, 2 usage, 130 Ctrl-C, 143 SIGTERM (where the
    command stops on it as on Ctrl-C).
    """
    args = build_parser().parse_args(argv)
    try:
        return int(args.run(args))
    except ArmplanError as error:
        return report_error(error, getattr(args, "json", False))
    except Terminated:  # SIGTERM where the command handles it (demo)
        sys.stderr.write("armplan: terminated\n")
        return TERMINATED_CODE
    except KeyboardInterrupt:
        sys.stderr.write("armplan: interrupted\n")
        return INTERRUPTED_CODE
    except BrokenPipeError:  # e.g. `armplan ... | head`: the reader left
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error at exit
        return 0


if __name__ == "__main__":
    raise SystemExit(main())
