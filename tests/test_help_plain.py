"""Every ``--help`` of armplan's commands and processes is plain text.

Descriptions taken from module docstrings showed their reST markup as
written: ``python -m bridge --help`` printed ``:class:`~shared.messages.
ExecuteRequest` `` and double backticks, ``armplan demo --help`` the
literal ````armplan demo [--out DIR]````.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from armplan.cli.main import build_parser
from shared.text.plain import plain_text

ROOT = Path(__file__).resolve().parents[1]
#: A Sphinx role or an inline literal, as a docstring writes them.
MARKUP = re.compile(r":(class|func|mod|meth|attr|data|exc|obj):|``")
#: Every ``python -m`` process armplan starts or documents.
PROCESSES = [
    "bridge",
    "bridge.serve",
    "bridge.sim",
    "shared.bus.router",
    *sorted(
        f"services.{path.parent.name}"
        for path in (ROOT / "services").glob("*/__main__.py")
    ),
]


def parsers(
    parser: argparse.ArgumentParser, path: str
) -> Iterator[tuple[str, argparse.ArgumentParser]]:
    """``parser`` and every subparser under it, with its command path."""
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from parsers(sub, f"{path} {name}")


def marked(text: str) -> list[str]:
    """The lines of ``text`` that show reST markup."""
    return [line for line in text.splitlines() if MARKUP.search(line)]


def test_every_armplan_commands_help_is_plain() -> None:
    found = list(parsers(build_parser(), "armplan"))
    assert {"armplan demo", "armplan faults", "armplan demos synth"} <= {
        path for path, _ in found
    }
    shown = {path: marked(parser.format_help()) for path, parser in found}
    assert {path: lines for path, lines in shown.items() if lines} == {}


def test_the_demos_help_reads_its_docstring_plainly() -> None:
    """The docstring is still the description, its markup rendered."""
    demo = dict(parsers(build_parser(), "armplan"))["armplan demo"]
    assert "armplan demo [--out DIR]: the paper's handover task" in " ".join(
        demo.format_help().split()
    )


@pytest.mark.parametrize("module", PROCESSES)
def test_every_process_help_is_plain(module: str) -> None:
    done = subprocess.run(
        [sys.executable, "-m", module, "--help"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=ROOT,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("usage: python -m")
    assert marked(done.stdout) == []


def test_the_bridges_help_names_the_classes_it_reads() -> None:
    """A role shows its target (its last part after ``~``), a literal its text."""
    done = subprocess.run(
        [sys.executable, "-m", "bridge", "--help"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=ROOT,
        check=False,
    )
    text = " ".join(done.stdout.split())
    assert "Reads one ExecuteRequest per line (JSON)" in text
    assert "(bridge.address; an address not tcp://HOST:PORT exits 1" in text


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        (":class:`~shared.messages.ExecuteRequest`", "ExecuteRequest"),
        (":mod:`bridge.address`", "bridge.address"),
        (":py:meth:`~a.B.c` and :func:`f`", "c and f"),
        (":func:`the title <a.b>`", "the title"),
        ("``armplan demo [--out DIR]``: the ``x``", "armplan demo [--out DIR]: the x"),
        ("no markup: `one` backtick", "no markup: `one` backtick"),
    ],
)
def test_plain_text_renders_roles_and_literals(text: str, shown: str) -> None:
    assert plain_text(text) == shown


def test_plain_text_keeps_none() -> None:
    assert plain_text(None) is None
