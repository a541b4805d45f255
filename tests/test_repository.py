"""The repository's own contracts: README's two commands and CI."""

from __future__ import annotations

import pathlib
import subprocess

ROOT = pathlib.Path(__file__).parent.parent


def _readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    block = text.split("```sh\n", 1)[1].split("```", 1)[0]
    return [line for line in block.splitlines() if line.strip()]


def test_readme_opens_with_exactly_two_commands() -> None:
    """The first block holds an install-and-run line and an install-and-test line."""
    commands = _readme_commands()
    assert len(commands) == 2
    assert (ROOT / "README.md").read_text().index("```sh") < 20
    run, test = commands
    assert "pip install" in run and "armplan" in run
    assert (
        "pip install" in test and "pytest" in test and "ruff" in test and "mypy" in test
    )


def test_ci_runs_the_readme_test_command() -> None:
    """.ci/run extracts exactly the README's second command."""
    script = (ROOT / ".ci" / "run").read_text()
    awk = script.split("command=$(", 1)[1].split(" README.md)", 1)[0]
    out = subprocess.run(
        ["bash", "-c", f"{awk} README.md"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    assert out.stdout.strip() == _readme_commands()[1]
