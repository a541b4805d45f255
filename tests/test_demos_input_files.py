"""demos and fit refuse a bad output, an output that is an input, and duplicates."""

from __future__ import annotations

import json
import os
import pathlib

import pytest

from armplan.cli.main import main
from shared.demos import read_demos
from shared.errors import DemoFileError
from tests.test_demos_input_csv import arm_rows, write_csv


@pytest.fixture(scope="module")
def demos(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    path = tmp_path_factory.mktemp("demos") / "syn.mcap"
    argv = ["demos", "synth", "-o", str(path), "--subjects", "1", "--trials", "1"]
    assert main(argv) == 0
    return path


def _error(capsys: pytest.CaptureFixture[str]) -> str:
    return capsys.readouterr().err


def test_fit_refuses_an_empty_output_name(
    demos: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o "" is a typed error, not a ValueError from pathlib."""
    assert main(["fit", str(demos), "-o", ""]) == 1
    assert _error(capsys) == "armplan: error: output '' is not a file name\n"


def test_fit_refuses_an_output_in_a_missing_folder(
    demos: pathlib.Path, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Refused before the fit, not after it."""
    out = tmp_path / "no" / "m.json"
    assert main(["fit", str(demos), "-o", str(out)]) == 1
    assert _error(capsys) == (
        f"armplan: error: cannot write {out}: No such file or directory\n"
    )


def test_fit_refuses_to_overwrite_its_input(
    demos: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o naming the demonstration file (by another spelling) leaves it intact."""
    before = demos.read_bytes()
    other = os.path.join(str(demos.parent), ".", demos.name)
    assert main(["fit", str(demos), "-o", other]) == 1
    assert _error(capsys) == (
        f"armplan: error: output {demos} is also an input ({demos}): writing it "
        "would destroy that input; choose another output name\n"
    )
    assert demos.read_bytes() == before


@pytest.mark.parametrize("command", ["fit", "demos info"])
def test_a_demonstration_file_given_twice_is_refused(
    demos: pathlib.Path,
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
    command: str,
) -> None:
    """Its trials would count twice: the error names both spellings."""
    link = tmp_path / "link.mcap"
    link.symlink_to(demos)
    output = ["-o", str(tmp_path / "m.json")] if command == "fit" else []
    assert main([*command.split(), *output, str(demos), str(link)]) == 1
    assert _error(capsys) == (
        f"armplan: error: {link}: given twice (also as {demos}): its trials "
        "would be counted twice\n"
    )
    assert not (tmp_path / "m.json").exists()


def test_read_demos_refuses_one_file_twice(demos: pathlib.Path) -> None:
    """The check sits in the reader, so every command and the service get it."""
    with pytest.raises(DemoFileError, match="given twice: its trials"):
        read_demos([demos, demos])


def _import_setup(tmp_path: pathlib.Path) -> tuple[pathlib.Path, pathlib.Path]:
    csv_path = write_csv(tmp_path / "mc2.csv", arm_rows(0))
    markers = tmp_path / "map.json"
    markers.write_text(
        json.dumps({"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"})
    )
    return csv_path, markers


@pytest.mark.parametrize("target", ["mc2.csv", "map.json"])
def test_import_refuses_to_overwrite_an_input(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], target: str
) -> None:
    """Neither the capture nor the marker map may be the output."""
    csv_path, markers = _import_setup(tmp_path)
    out = tmp_path / target
    before = out.read_bytes()
    argv = ["demos", "import", "--markers", str(markers), "-o", str(out), str(csv_path)]
    assert main(argv) == 1
    assert f"output {out} is also an input" in _error(capsys)
    assert out.read_bytes() == before


def test_import_refuses_a_file_given_twice(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """mc2.csv and ./mc2.csv are one file; no output is written."""
    csv_path, markers = _import_setup(tmp_path)
    again = os.path.join(str(tmp_path), ".", "mc2.csv")
    out = tmp_path / "x.mcap"
    argv = ["demos", "import", "--markers", str(markers), "-o", str(out)]
    assert main([*argv, str(csv_path), again]) == 1
    assert _error(capsys) == (
        f"armplan: error: {again}: given twice (also as {csv_path}): its trials "
        "would be counted twice\n"
    )
    assert not out.exists()


def test_synth_refuses_a_directory_as_output(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A folder is no output file."""
    assert main(["demos", "synth", "-o", str(tmp_path)]) == 1
    assert (
        _error(capsys) == f"armplan: error: cannot write {tmp_path}: Is a directory\n"
    )


def test_two_people_under_one_name_are_refused(
    demos: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    """Two synthetic sets of other seeds both name their person S01: refused
    naming both files and arms (the later arm used to replace the earlier)."""
    other = tmp_path / "other.mcap"
    argv = ["demos", "synth", "-o", str(other), "--subjects", "1", "--trials", "1"]
    assert main([*argv, "--seed", "1"]) == 0
    with pytest.raises(DemoFileError, match=rf"subject 'S01' has arms .* in {demos}"):
        read_demos([demos, other])
