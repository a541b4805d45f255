"""demos and fit refuse a bad output, an output that is an input, and duplicates."""

from __future__ import annotations

import csv
import json
import os
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from shared.demos import read_demos, synthesize, write_demos
from shared.demos.demo_file import SYNTHETIC
from shared.demos.trial import DemoSet
from shared.errors import DemoFileError
from tests.test_demos_c3d import write_reach_c3d
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


def test_import_of_a_folder_says_to_give_its_files(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A folder of captures was "expected a .c3d or .csv file"; now the error
    says it is a folder and to give the files in it. Nothing is written."""
    _, markers = _import_setup(tmp_path)
    out = tmp_path / "x.mcap"
    argv = ["demos", "import", "--markers", str(markers), "-o", str(out)]
    assert main([*argv, str(tmp_path)]) == 1
    assert _error(capsys) == (
        f"armplan: error: {tmp_path}: a folder, not a capture file: give the "
        f"files in it (e.g. {tmp_path / '*.c3d'} or {tmp_path / '*.csv'})\n"
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
    """Two synthetic sets of other seeds both name their person S01, arms
    within 10 % (one person, as far as the arm tells), both with trials 0-15:
    refused naming both files (the later set used to replace the earlier's
    arm, then to need the very same arm)."""
    other = tmp_path / "other.mcap"
    argv = ["demos", "synth", "-o", str(other), "--subjects", "1", "--trials", "1"]
    assert main([*argv, "--seed", "1"]) == 0
    with pytest.raises(
        DemoFileError,
        match=rf"trial 0 of subject 'S01' \(right arm\) is also in {demos}",
    ):
        read_demos([demos, other])


def _import(
    tmp_path: pathlib.Path, name: str, rows: list[list[str]], *more: str
) -> pathlib.Path:
    """Import CSV ``rows`` (subject P01) into ``name``.mcap; the output's path."""
    csv_path = write_csv(tmp_path / f"{name}.csv", rows)
    markers = tmp_path / "p01.json"
    markers.write_text(
        json.dumps(
            {"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB", "subject": "P01"}
        )
    )
    out = tmp_path / f"{name}.mcap"
    argv = ["demos", "import", str(csv_path), "--markers", str(markers)]
    assert main([*argv, "-o", str(out), *more]) == 0
    return out


def test_one_person_imported_twice_is_one_subject(tmp_path: pathlib.Path) -> None:
    """Two sessions of P01 whose arms measure 3 % apart (markers placed
    again), imported apart: one person, whose trials both count; the arm
    kept is the first file's. (An absolute 1e-9 m used to refuse them.)"""
    first = _import(tmp_path, "monday", arm_rows(0) + arm_rows(1))
    second = _import(tmp_path, "tuesday", arm_rows(2, scale=1.03), "--first-trial", "2")
    demos = read_demos([first, second])
    assert list(demos.subjects) == ["P01"]
    assert [t.trial for t in demos.trials] == [0, 1, 2]
    assert demos.subjects["P01"].upper_arm == pytest.approx(0.3, abs=1e-6)


def test_two_arms_more_than_ten_percent_apart_are_two_people(
    tmp_path: pathlib.Path,
) -> None:
    """12 % longer arms under one name: refused, naming both files and arms."""
    first = _import(tmp_path, "p", arm_rows(0))
    second = _import(tmp_path, "q", arm_rows(0, scale=1.12), "--first-trial", "1")
    with pytest.raises(DemoFileError) as caught:
        read_demos([first, second])
    assert caught.value.message == (
        f"{second}: subject 'P01' has arms of 0.336 + 0.280 m here and 0.300 + "
        f"0.250 m in {first}, more than 10% apart: two people under one name? "
        'Give each its own (the marker map\'s "subject")'
    )


def test_a_copy_of_a_demonstration_file_is_refused(tmp_path: pathlib.Path) -> None:
    """A byte copy under another name used to count every trial twice."""
    first = _import(tmp_path, "a", arm_rows(0) + arm_rows(1))
    copy = tmp_path / "a2.mcap"
    copy.write_bytes(first.read_bytes())
    with pytest.raises(DemoFileError) as caught:
        read_demos([first, copy])
    assert caught.value.message == (
        f"{copy}: trial 0 of subject 'P01' holds the samples of trial 0 of "
        f"subject 'P01' in {first} (positions within 0.1 mm): one recording "
        "given twice (a copy, or two exports of one session) would count twice"
    )


def test_one_trial_number_in_two_files_is_refused(tmp_path: pathlib.Path) -> None:
    """Two imports of P01 each numbered from 0: trial 0 is two recordings
    (the experiments would average them as one reach); refused naming both
    files and the number to start the later one's from."""
    first = _import(tmp_path, "a", arm_rows(0) + arm_rows(1))
    second = _import(tmp_path, "b", arm_rows(2))
    with pytest.raises(DemoFileError) as caught:
        read_demos([first, second])
    assert caught.value.message == (
        f"{second}: trial 0 of subject 'P01' (right arm) is also in {first}, another "
        "recording under the same number (each `armplan demos import` numbers "
        "its trials from 0): import the files in one `armplan demos import`, or "
        "number this file's from 2 (`armplan demos import --first-trial 2`)"
    )


def _both_arms_csv(path: pathlib.Path) -> pathlib.Path:
    """A CSV of trials 0 and 1 with P01's right arm (columns R...) and its
    mirror image, the left arm (columns L..., y negated), side by side."""
    rows = arm_rows(0) + arm_rows(1)
    markers = ("SHO", "ELB", "WRB")
    header = ["time", "trial"]
    header += [f"{s}{m}_{a}" for s in "RL" for m in markers for a in "xyz"]
    mirror = np.tile([1.0, -1.0, 1.0], 3)
    cells = [r + [f"{v:.6f}" for v in mirror * np.array(r[2:], float)] for r in rows]
    with open(path, "w", newline="") as stream:
        csv.writer(stream).writerows([header, *cells])
    return path


def _import_arm(tmp_path: pathlib.Path, table: pathlib.Path, arm: str) -> str:
    """``armplan demos import`` of ``table``'s ``arm`` (marker map of that
    arm's columns); the output's path."""
    side = arm[0].upper()
    markers = tmp_path / f"map_{arm}.json"
    names = {"shoulder": "SHO", "elbow": "ELB", "wrist": "WRB"}
    fields = {key: side + name for key, name in names.items()}
    markers.write_text(json.dumps(fields | {"arm": arm, "subject": "P01"}))
    out = tmp_path / f"both_{arm}.mcap"
    argv = ["demos", "import", str(table), "--markers", str(markers)]
    assert main([*argv, "-o", str(out)]) == 0
    return str(out)


def test_one_trial_number_on_two_arms_is_two_reaches(tmp_path: pathlib.Path) -> None:
    """One CSV of both arms imported once per arm: trial 0 of the right arm
    and trial 0 of the left are two reaches, read together (they were
    refused as one number recorded twice)."""
    table = _both_arms_csv(tmp_path / "both.csv")
    right, left = (_import_arm(tmp_path, table, arm) for arm in ("right", "left"))
    demos = read_demos([right, left])
    read = [(t.arm.value, t.trial, t.source) for t in demos.trials]
    assert read == [
        ("right", 0, right),
        ("right", 1, right),
        ("left", 0, left),
        ("left", 1, left),
    ]


def test_both_arms_in_one_file_are_two_reaches(tmp_path: pathlib.Path) -> None:
    """A file holding trial 0 of each arm, one after the other, reads as two
    trials (the samples of both used to be joined into one trial)."""
    table = _both_arms_csv(tmp_path / "both.csv")
    both = read_demos([_import_arm(tmp_path, table, a) for a in ("right", "left")])
    pair = [t for t in both.trials if t.trial == 0]
    path = tmp_path / "pair.mcap"
    write_demos(path, DemoSet(both.subjects, pair))
    read = read_demos(path)
    assert [(t.arm.value, t.trial, len(t.times)) for t in read.trials] == [
        ("right", 0, 30),
        ("left", 0, 30),
    ]


def test_one_trial_number_in_two_synthetic_sets_gets_their_advice(
    tmp_path: pathlib.Path,
) -> None:
    """Two `armplan demos synth` sets: trial 0 of one subject twice. The
    advice was to re-import them, which synthetic sets cannot be."""
    first, second = tmp_path / "a.mcap", tmp_path / "b.mcap"
    for path, seed in ((first, 1), (second, 2)):
        demos = synthesize(seed, subjects=1, trials=2)
        write_demos(path, demos, source=f"{SYNTHETIC}{seed}")
    with pytest.raises(DemoFileError) as caught:
        read_demos([first, second])
    assert caught.value.message.endswith(
        "(each `armplan demos synth` set numbers its trials from 0): a synthetic "
        "set is read alone; make one with more --subjects or --trials instead"
    )
    assert "demos import" not in caught.value.message


def test_import_refuses_a_copy_under_another_name(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """mc2.csv and a copy of it in one import: the same trial twice."""
    csv_path, markers = _import_setup(tmp_path)
    copy = tmp_path / "copy.csv"
    copy.write_bytes(csv_path.read_bytes())
    out = tmp_path / "x.mcap"
    argv = ["demos", "import", "--markers", str(markers), "-o", str(out)]
    assert main([*argv, str(csv_path), str(copy)]) == 1
    lines = f"lines 2-{1 + len(arm_rows(0))}"  # line k + 2 holds row k
    assert _error(capsys) == (
        f"armplan: error: {copy}: trial 1 of subject 'copy' ({lines}) holds the "
        f"samples of trial 0 of subject 'mc2' ({lines}) in {csv_path} (positions "
        "within 0.1 mm): one "
        "recording given twice (a copy, or two exports of one session) would "
        "count twice\n"
    )
    assert not out.exists()


@pytest.mark.parametrize("suffix", [".c3d", ".csv"])
def test_a_file_name_too_long_for_a_subject_is_refused_before_any_work(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], suffix: str
) -> None:
    """A lab's take name of 80 characters became the subject's name (the map
    had no "subject"), and the import read every file, then failed writing:
    "out.mcap: not written, ... name: String should have at most 64
    characters". It is refused before the files are read, saying what to
    give; the first file, a good one, is not read (no note of its gaps)."""
    good = write_csv(tmp_path / "good.csv", arm_rows(0))
    long = tmp_path / (
        "Session_2026_11_27_Participant_042_Fast_Reach_Point_13_Take_07" + "_x" * 8
    )
    write_csv(long.with_suffix(".csv"), arm_rows(1))
    if suffix == ".c3d":
        write_reach_c3d(long.with_suffix(".c3d"))
    long = long.with_suffix(suffix)
    markers = tmp_path / "map.json"
    markers.write_text(
        json.dumps({"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"})
    )
    out = tmp_path / "out.mcap"
    args = ["demos", "import", str(good), str(long), "--markers", str(markers)]
    assert main([*args, "-o", str(out)]) == 1
    assert _error(capsys) == (
        f"armplan: error: {long}: the subject's name would be the file's, "
        f"{len(long.stem)} characters, over the 64 a subject's name may have: "
        'give "subject" in the marker map (one map per subject)\n'
    )
    assert not out.exists()
