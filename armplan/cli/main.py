"""Entry point of the ``armplan`` command."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from armplan import __version__
from armplan.cli import bench, fk, ik
from armplan.cli.output import report_error
from armplan.cli.parsing import ArgumentParser
from shared.errors import ArmplanError

COMMANDS = (fk, ik, bench)


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
    for command in COMMANDS:
        command.add_parser(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run one command; returns the exit code (0 ok, 1 armplan error, 2 usage)."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.run(args))
    except ArmplanError as error:
        return report_error(error, getattr(args, "json", False))
    except KeyboardInterrupt:
        sys.stderr.write("armplan: interrupted\n")
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
