"""Every command, subcommand, argument and option of ``armplan`` says what it is."""

from __future__ import annotations

import argparse
from collections.abc import Iterator

from armplan.cli.main import build_parser


def arguments(
    parser: argparse.ArgumentParser, path: str
) -> Iterator[tuple[str, argparse.Action]]:
    """Every action of ``parser`` and its subparsers, with its command path."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from arguments(sub, f"{path} {name}")
        else:
            yield path, action


def test_every_argument_and_option_has_help() -> None:
    """An option shown in ``--help`` without a word is a guess for its user."""
    found = list(arguments(build_parser(), "armplan"))
    assert len(found) > 100  # the walk reached the subcommands
    silent = [
        f"{path} {'/'.join(action.option_strings) or action.dest}"
        for path, action in found
        if not action.help
    ]
    assert silent == []
