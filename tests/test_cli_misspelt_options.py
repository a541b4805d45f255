"""A misspelt option is named, and options are taken only as spelt in full.

``armplan plan --targt 0.12 -0.13 0.05`` said only ``one of the arguments
--target --wrist-path --task is required``, never naming ``--targt``;
``--dwel 0.5`` was silently taken for ``--dwell``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from collections.abc import Iterator

import pytest
from armplan_cli import armplan

from armplan.cli.main import build_parser


def parsers(parser: argparse.ArgumentParser) -> Iterator[argparse.ArgumentParser]:
    """``parser`` and every subparser under it."""
    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from parsers(sub)


def test_a_misspelt_option_is_named_before_the_missing_one() -> None:
    done = armplan("plan", "--targt", "0.12", "-0.13", "0.05")
    assert done.returncode == 2
    assert done.stderr.startswith("usage: armplan plan")
    assert done.stderr.endswith(
        "armplan plan: error: unrecognized arguments: --targt\n"
    )
    alone = armplan("plan", "--arm", "left")  # nothing misspelt: as before
    assert alone.returncode == 2
    assert alone.stderr.endswith(
        "armplan plan: error: one of the arguments --target --wrist-path --task "
        "is required\n"
    )


@pytest.mark.parametrize(
    ("args", "unknown"),
    [
        (["plan", "--target", "0.12", "-0.13", "0.05", "--dwel", "0.5"], "--dwel 0.5"),
        (["stop", "--reas", "x"], "--reas x"),
    ],
)
def test_an_abbreviated_option_is_refused(args: list[str], unknown: str) -> None:
    with pytest.raises(SystemExit) as exited:
        build_parser().parse_args(args)
    assert exited.value.code == 2
    done = armplan(*args)
    assert done.returncode == 2
    assert done.stderr.endswith(f"error: unrecognized arguments: {unknown}\n")


def test_no_parser_takes_abbreviations() -> None:
    found = list(parsers(build_parser()))
    assert len(found) > 20
    assert [p.prog for p in found if p.allow_abbrev] == []


@pytest.mark.parametrize(
    "value", ["-x y.json", "--odd name.json"], ids=["dash", "double-dash"]
)
def test_a_value_with_a_space_is_not_called_an_option(
    value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """argparse takes a dashed argument with a space for a value: ``decide
    --model '-x y.json'`` with no target was refused as 'unrecognized
    arguments: -x y.json', not for the target it lacks."""
    with pytest.raises(SystemExit) as exited:
        build_parser().parse_args(["decide", "--model", value])
    assert exited.value.code == 2
    assert capsys.readouterr().err.endswith(
        "armplan decide: error: one of the arguments --target --wrist-path --grid "
        "is required\n"
    )


@pytest.mark.parametrize(
    "module",
    [
        "services.ik",
        "bridge.serve",
        "bridge",
        "bridge.sim",
        "services.recorder",
        "shared.bus.router",
    ],
)
def test_the_processes_take_options_only_as_spelt_in_full(module: str) -> None:
    """`python -m services.ik --hel` printed the help (an abbreviation of
    --help, as --conn was of --connect); like armplan's commands, the
    processes now refuse an option not spelt in full."""
    done = subprocess.run(
        [sys.executable, "-m", module, "--hel"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2, done.stdout
    assert "unrecognized arguments: --hel" in done.stderr
