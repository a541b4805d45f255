"""``armplan export``: an output path it cannot write, a trajectory too long.

Each is refused with one line naming the path (or the file) and the reason,
exit code 1, and nothing written.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from armplan.cli.main import main
from bridge.frames import MAX_FRAMES, frames_from_trajectory
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.python_export import write_python
from shared.errors import InvalidInputError
from shared.messages import Trajectory
from shared.robot.postures import rest

FORMATS = ("python", "choregraphe")


def trajectory() -> Trajectory:
    start = rest("right")
    return minimum_jerk_trajectory(
        "right", [start, start + np.array([-0.6, -0.3, -0.4, 0.5, 0.7])], [0.6]
    )


def held_until(end: float) -> Trajectory:
    """The reach, then its last posture held still until ``end`` [s]."""
    reach = trajectory().model_dump()
    for name in ("positions", "wrist_path", "primitives"):
        reach[name].append(reach[name][-1])
    for name in ("velocities", "accelerations"):
        reach[name].append([0.0] * len(reach["joint_names"]))
    reach["times"].append(end)
    return Trajectory.model_validate(reach)


@pytest.fixture
def source(tmp_path: Path) -> Path:
    path = tmp_path / "trajectory.json"
    path.write_text(trajectory().to_json())
    return path


def export(
    capsys: pytest.CaptureFixture[str], fmt: str, source: Path, output: str
) -> tuple[int, str]:
    """Exit code and standard error of ``armplan export FMT SOURCE -o OUTPUT``."""
    code = main(["export", fmt, str(source), "-o", output])
    return code, capsys.readouterr().err


def exported(capsys: pytest.CaptureFixture[str], source: Path, output: Path) -> str:
    """Standard output of a successful ``armplan export python``."""
    assert main(["export", "python", str(source), "-o", str(output)]) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_folder_as_output_is_refused(
    fmt: str, source: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o DIR names the folder and says it is one, instead of IsADirectoryError."""
    folder = tmp_path / "folder"
    folder.mkdir()
    code, err = export(capsys, fmt, source, str(folder))
    assert code == 1
    assert err == f"armplan: error: cannot write {folder}: Is a directory\n"
    assert list(folder.iterdir()) == []


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_output_in_a_missing_folder_is_refused(
    fmt: str, source: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o /missing/x.py: the path and "No such file or directory", nothing made."""
    output = tmp_path / "missing" / "x.py"
    code, err = export(capsys, fmt, source, str(output))
    assert code == 1
    assert err == f"armplan: error: cannot write {output}: No such file or directory\n"
    assert not output.parent.exists()


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_output_under_a_file_is_refused(
    fmt: str, source: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o FILE/x.py: the path and "Not a directory"."""
    output = source / "x.py"
    code, err = export(capsys, fmt, source, str(output))
    assert code == 1
    assert err == f"armplan: error: cannot write {output}: Not a directory\n"


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_empty_output_is_refused(
    fmt: str,
    source: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """-o "" is no file name (it used to try to write the folder ".")."""
    monkeypatch.chdir(tmp_path)
    code, err = export(capsys, fmt, source, "")
    assert code == 1
    assert err == "armplan: error: output '' is not a file name\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["trajectory.json"]


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_trajectory_of_too_many_frames_is_refused(
    fmt: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A last sample at 80 000 s (at 1e6 s it hung, filling the memory with
    frames; times now stay within a day) is refused with the frame count and
    the cap, before any frame is made."""
    source = tmp_path / "t_gap.json"
    source.write_text(held_until(8e4).to_json())
    output = tmp_path / "x.out"
    code, err = export(capsys, fmt, source, str(output))
    assert code == 1
    assert err == (
        "armplan: error: a trajectory of 80000 s at 25 fps is 2000000 frames, "
        f"more than {MAX_FRAMES}: lower the frame rate or split the movement\n"
    )
    assert not output.exists()


def test_a_trajectory_of_the_most_frames_is_exported(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The cap itself is allowed: 30 minutes is 45000 frames at 25 fps."""
    source = tmp_path / "long.json"
    source.write_text(held_until(MAX_FRAMES / 25.0).to_json())
    output = tmp_path / "long.py"
    assert exported(capsys, source, output).startswith(
        f"wrote {output}: {MAX_FRAMES} frames at 25 fps"
    )


def test_the_writer_names_a_path_it_cannot_write(tmp_path: Path) -> None:
    """write_python itself turns the OS's error into a typed one."""
    frames = frames_from_trajectory(trajectory())
    with pytest.raises(InvalidInputError) as caught:
        write_python(frames, tmp_path)
    assert caught.value.message == f"cannot write {tmp_path}: Is a directory"
    assert caught.value.field == "output"


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_output_that_is_the_input_is_refused(
    fmt: str, source: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o naming the trajectory itself (it was overwritten with the export)
    is refused, naming both, and the trajectory is left as it was."""
    before = source.read_text()
    code, err = export(capsys, fmt, source, str(source))
    assert code == 1
    assert err == (
        f"armplan: error: output {source} is also an input ({source}): writing "
        "it would destroy that input; choose another output name\n"
    )
    assert source.read_text() == before


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_plans_error_file_is_named_as_one(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, fmt: str
) -> None:
    """`armplan plan --json > f.json` for an unreachable target writes the
    error there; exporting f.json said "invalid Trajectory: arm: Field
    required; and 8 more problems". Now it says the file holds the plan's
    error, and which."""
    failed = tmp_path / "failed.json"
    assert main(["plan", "--target", "0.5", "0.5", "0.5", "--json"]) == 1
    failed.write_text(capsys.readouterr().out)
    output = tmp_path / f"out.{fmt}"
    code, err = export(capsys, fmt, failed, str(output))
    assert code == 1
    assert err.startswith(
        f"armplan: error: {failed} holds an armplan error (unreachable_target), "
        "not a trajectory: the command that wrote it failed: target (0.5, 0.5, "
        "0.5) m is 0.8761 m from the right shoulder"
    )
    assert not output.exists()


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("json_summary", [False, True])
def test_an_export_to_standard_output_holds_the_export_alone(
    fmt: str, json_summary: bool, source: Path, tmp_path: Path
) -> None:
    """``-o /dev/stdout > play.py``: play.py holds the export as ``-o``
    writes it, and the summary goes to standard error. The summary used to
    go to standard output as well: into a pipe it trailed the script (a
    Python syntax error), and into a file it overwrote the script's first
    line, as the two opens of the file each wrote from its start."""
    direct = tmp_path / "direct.out"
    assert main(["export", fmt, str(source), "-o", str(direct)]) == 0
    piped = tmp_path / "piped.out"
    command = [sys.executable, "-m", "armplan", "export", fmt, str(source)]
    command += ["-o", "/dev/stdout", *(["--json"] if json_summary else [])]
    with piped.open("w") as out:
        done = subprocess.run(
            command, stdout=out, stderr=subprocess.PIPE, text=True, timeout=120
        )
    assert done.returncode == 0, done.stderr
    assert piped.read_bytes() == direct.read_bytes()
    summary = done.stderr
    if json_summary:
        assert json.loads(summary)["path"] == "/dev/stdout"
    else:
        assert summary.startswith("wrote /dev/stdout: 15 frames at 25 fps")


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_export_to_stdout_with_stderr_there_too_holds_the_export_alone(
    fmt: str, source: Path, tmp_path: Path
) -> None:
    """``-o /dev/stdout > play.py 2>&1``: play.py holds the export alone.
    The summary, moved to standard error, went into the file all the same,
    over the script's first line (a syntax error); it is now dropped."""
    direct = tmp_path / "direct.out"
    assert main(["export", fmt, str(source), "-o", str(direct)]) == 0
    both = tmp_path / "both.out"
    command = [sys.executable, "-m", "armplan", "export", fmt, str(source)]
    with both.open("w") as out:
        done = subprocess.run(
            [*command, "-o", "/dev/stdout"],
            stdout=out,
            stderr=subprocess.STDOUT,
            timeout=120,
        )
    assert done.returncode == 0
    assert both.read_bytes() == direct.read_bytes()
