"""Every ``armplan`` option the documentation names exists.

The docs named ``armplan demo --rate``, an option ``armplan demo`` never
had (its rate is ``DemoOptions.rate``, set from Python). Each inline code
span that starts ``armplan COMMAND [SUBCOMMAND]`` in README.md and docs/ is
read against the real command line (``armplan.cli.main.build_parser``):
every ``--option`` in it must be one the command takes.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from armplan.cli.main import build_parser

ROOT = Path(__file__).resolve().parent.parent
_SPAN = re.compile(r"`(armplan [^`]+)`")
_OPTION = re.compile(r"--[a-z][a-z0-9-]*")


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _unknown_options(span: str, top: argparse.ArgumentParser) -> list[str]:
    """The ``--options`` of ``span`` (``armplan ...``) its command does not take."""
    words = span.split()[1:]
    parsers = [top]
    while words and all(
        name in _subcommands(parsers[0]) for name in words[0].split("|")
    ):  # "similarity|handover|pace": each of them
        parsers = [_subcommands(parsers[0])[name] for name in words.pop(0).split("|")]
    if parsers == [top]:
        return []  # not a command (prose such as "armplan's")
    options = [m.group(0) for w in words if (m := _OPTION.match(w.split("=")[0]))]
    return [
        option
        for parser in parsers
        for option in options
        if option not in {o for a in parser._actions for o in a.option_strings}
    ]


def test_every_option_the_docs_name_exists() -> None:
    top = build_parser()
    wrong = []
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = path.read_text(encoding="utf-8").replace("\n", " ")
        for span in _SPAN.findall(text):
            wrong += [
                f"{path.name}: `{span}`: {o}" for o in _unknown_options(span, top)
            ]
    assert wrong == []


def test_an_option_a_command_lacks_is_found() -> None:
    """The check itself: the old docs' ``armplan demo --rate`` is caught."""
    top = build_parser()
    assert _unknown_options("armplan demo --rate 30", top) == ["--rate"]
    assert _unknown_options("armplan demo --robot tcp://IP:9559", top) == []
    assert _unknown_options("armplan demos synth --subjects 1", top) == []
    assert _unknown_options("armplan experiment pace|similarity --nope", top) == [
        "--nope",
        "--nope",
    ]
