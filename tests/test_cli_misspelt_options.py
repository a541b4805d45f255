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
        "armplan plan: error: unrecognized arguments: --targt "
        "(did you mean --target?)\n"
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
        (
            ["plan", "--target", "0.12", "-0.13", "0.05", "--dwel", "0.5"],
            "--dwel 0.5 (did you mean --dwell?)",
        ),
        (["stop", "--reas", "x"], "--reas x (did you mean --reason?)"),
    ],
)
def test_an_abbreviated_option_is_refused(args: list[str], unknown: str) -> None:
    with pytest.raises(SystemExit) as exited:
        build_parser().parse_args(args)
    assert exited.value.code == 2
    done = armplan(*args)
    assert done.returncode == 2
    assert done.stderr.endswith(
        f"armplan {args[0]}: error: unrecognized arguments: {unknown}\n"
    )


@pytest.mark.parametrize(
    ("args", "error"),
    [
        (
            ["fit", "--timout", "5", "demos.mcap"],
            "armplan fit: error: unrecognized arguments: --timout "
            "(did you mean --timeout?)",
        ),
        (
            ["demos", "import", "a.c3d", "--markrs", "m.json", "-o", "d.mcap"],
            "armplan demos import: error: unrecognized arguments: --markrs "
            "(did you mean --markers?)",
        ),
        (
            ["plan", "--target", "0.1", "0", "0", "--dwel", "1", "--jsn"],
            "armplan plan: error: unrecognized arguments: --dwel 1 --jsn "
            "(did you mean --dwell for --dwel, --json for --jsn?)",
        ),
        (
            ["fit", "--zzz", "demos.mcap"],
            "armplan fit: error: unrecognized arguments: --zzz",
        ),
        (
            ["--verison"],
            "armplan: error: unrecognized arguments: --verison "
            "(did you mean --version?)",
        ),
        (  # given to armplan, not to fit: fit's --timeout is not armplan's
            ["--timout", "fit", "demos.mcap"],
            "armplan: error: unrecognized arguments: --timout",
        ),
        (  # after '--' a value, never a misspelt option
            ["plan", "--target", "0.1", "0", "0", "--", "--dwel"],
            "armplan plan: error: unrecognized arguments: -- --dwel",
        ),
    ],
    ids=["subcommand", "nested", "two", "none-close", "top", "before-command", "--"],
)
def test_a_misspelt_option_is_reported_by_its_command_with_the_closest(
    args: list[str], error: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """``armplan fit --timout 5`` said ``armplan: error: unrecognized
    arguments: --timout`` under the bare ``armplan``'s usage: now the
    command's usage and name, and the option it is closest to."""
    with pytest.raises(SystemExit) as exited:
        build_parser().parse_args(args)
    assert exited.value.code == 2
    err = capsys.readouterr().err
    assert err.endswith(error + "\n")
    command = error.split(": error:")[0]
    assert err.startswith(f"usage: {command} ")


@pytest.mark.parametrize(
    ("module", "args", "error"),
    [
        (
            "services.ik",
            ["--wiat", "3"],
            "python -m services.ik: error: unrecognized arguments: --wiat 3 "
            "(did you mean --wait?)",
        ),
        (  # --prog is hidden: never offered
            "bridge.sim",
            ["--prot", "3"],
            "python -m bridge.sim: error: unrecognized arguments: --prot 3",
        ),
    ],
    ids=["service", "hidden"],
)
def test_a_process_names_the_option_closest_to_a_misspelt_one(
    module: str, args: list[str], error: str
) -> None:
    done = subprocess.run(
        [sys.executable, "-m", module, *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2
    assert done.stderr.endswith(error + "\n")


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
