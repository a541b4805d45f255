"""armplan decide: JSON contract, wrist-path CSV, Fig. 7 plot, grid, clear errors."""

from __future__ import annotations

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest
from test_demos_input_csv import MARKERS, arm_rows, write_csv

from armplan.cli.main import main
from services.fit import default_model, save_model
from shared.demos import DemoSet, synthesize, write_demos
from shared.demos.csv_import import read_csv
from shared.messages import Decision, parse
from shared.primitives import BY_NAME


def armplan(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_target_json_is_a_decision_message() -> None:
    """--json prints the Decision: per point primitive, matrix and every g."""
    out = armplan(
        "decide", "--arm", "right", "--target", "0.12", "-0.09", "0.05", "--json"
    )
    assert out.returncode == 0, out.stderr
    decision = parse(Decision, out.stdout)
    # 0.72 s at 100 Hz: the planner's human pace for the reach (was 0.8 s)
    assert decision.arm == "right" and len(decision.points) == 73
    assert decision.times[-1] == pytest.approx(0.72)
    for point in decision.points:
        assert point.matrix == BY_NAME[point.primitive].matrix
        assert len(point.g) == 8


def _reach_csv(path: pathlib.Path, times: np.ndarray, scale: float = 1.0) -> None:
    """A smooth 0.5 s reach sampled at ``times`` [s], written in [s] * ``scale``."""
    start, goal = np.array([0.011, -0.129, -0.058]), np.array([0.11, -0.1, 0.02])
    s = 3 * (times / 0.5) ** 2 - 2 * (times / 0.5) ** 3
    points = start + s[:, None] * (goal - start)
    rows = ["t,x,y,z"] + [
        f"{t * scale:.3f},{p[0]},{p[1]},{p[2]}"
        for t, p in zip(times, points, strict=True)
    ]
    path.write_text("\n".join(rows) + "\n")


def test_wrist_path_csv_keeps_its_times(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--wrist-path reads t,x,y,z and decides at exactly those times."""
    times = np.linspace(0.0, 0.5, 26)
    path = tmp_path / "path.csv"
    _reach_csv(path, times)
    assert main(["decide", "--wrist-path", str(path), "--json"]) == 0
    decision = parse(Decision, capsys.readouterr().out)
    np.testing.assert_allclose(decision.times, np.round(times, 3))


@pytest.mark.parametrize("command", ["decide", "plan"])
def test_wrist_path_csv_in_milliseconds_is_refused_as_such(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    """The 0.5 s reach with its times in ms was decided as a 500 s path (other
    primitives) and planned as a 500 s trajectory."""
    path = tmp_path / "ms.csv"
    _reach_csv(path, np.linspace(0.0, 0.5, 26), scale=1000.0)
    assert main([command, "--wrist-path", str(path)]) == 1
    err = capsys.readouterr().err
    assert f"{path}: invalid WristPath: " in err
    assert "the times step 20 apart (median), a sample rate of 0.05 Hz" in err
    assert "these look like milliseconds: divide them by 1000" in err


def test_plot_writes_a_png(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--plot draws the decision like Fig. 7 into a PNG file."""
    png = tmp_path / "decision.png"
    code = main(["decide", "--target", "0.12", "-0.1", "0.04", "--plot", str(png)])
    assert code == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = capsys.readouterr().out
    assert "S_R E_P W_P" in text and "mm from the goal" in text
    assert f"wrote {png}" in text


def test_a_plot_named_as_a_folder_is_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--plot DIR once wrote DIR.png beside it and said nothing: now refused."""
    code = main(["decide", "--target", "0.12", "-0.1", "0.04", "--plot", str(tmp_path)])
    assert code == 1
    assert "name a .png file" in capsys.readouterr().err
    assert not tmp_path.with_suffix(".png").exists()


def test_grid_prints_the_table_4_like_table(capsys: pytest.CaptureFixture[str]) -> None:
    """--grid prints one row per point with the primitives in order."""
    assert main(["decide", "--grid", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [row["point"] for row in data["nao"]] == list(range(1, 17))
    assert all(row["sequence"][0] == "S_R E_P W_P" for row in data["nao"][:4])


def test_grid_names_its_arm_and_each_points_position(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """--grid --arm left and --arm right printed the same bytes: now the
    header and the JSON name the arm, and each point's wrist target in the
    torso frame [m] is the other arm's mirror image (y negated)."""
    grids = {}
    for arm in ("Left", "right"):
        assert main(["decide", "--grid", "--arm", arm, "--json"]) == 0
        grids[arm.lower()] = json.loads(capsys.readouterr().out)
    assert [grids[a]["arm"] for a in ("left", "right")] == ["left", "right"]
    left = np.array([row["wrist"] for row in grids["left"]["nao"]])
    right = np.array([row["wrist"] for row in grids["right"]["nao"]])
    assert left.shape == (16, 3)
    assert np.abs(left - right * [1.0, -1.0, 1.0]).max() < 1e-9
    assert (right[:, 1] < 0.0).all()
    assert main(["decide", "--grid", "--arm", "LEFT"]) == 0
    assert capsys.readouterr().out.startswith(
        "NAO's left arm, decision along the planner's reach from hanging at rest"
    )


def _demos_file(tmp_path: pathlib.Path, synthetic: bool) -> str:
    """Two recorded reaches (imported: no grid point, no labels), with the
    16 synthetic grid reaches of one subject if ``synthetic``."""
    recorded, person = read_csv(
        write_csv(tmp_path / "rec.csv", arm_rows(1) + arm_rows(2)), MARKERS
    )
    grid = synthesize(0, subjects=1, trials=1) if synthetic else DemoSet({}, [])
    demos = DemoSet({**grid.subjects, person.name: person}, grid.trials + recorded)
    path = tmp_path / "demos.mcap"
    write_demos(path, demos)
    return str(path)


def test_grid_says_which_demonstrated_reaches_it_leaves_out(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Recorded reaches have no grid point: once silently dropped from
    --demos' table, now counted with the reason, in JSON and in the table."""
    path = _demos_file(tmp_path, synthetic=True)
    assert main(["decide", "--grid", "--demos", path, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert sum(row["trials"] for row in data["demonstrations"]) == 16
    assert data["left_out"] == {
        "total": 2,
        "no_point": 2,
        "no_labels": 0,
        "of": 18,
        "other_arm": 0,
    }
    assert main(["decide", "--grid", "--demos", path]) == 0
    assert (
        "2 of 18 demonstrated reaches left out of the table: 2 have no grid point "
        "(point 0, as recorded reaches are imported)"
    ) in capsys.readouterr().out


def test_grid_refuses_demos_it_can_use_none_of(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Only recorded reaches: the demonstrations' table would be empty (it
    was, without a word); refused naming the file, the count and why."""
    path = _demos_file(tmp_path, synthetic=False)
    assert main(["decide", "--grid", "--demos", path]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert (
        f"{path}: none of its 2 reaches can enter the grid table: 2 have no grid "
        "point (point 0, as recorded reaches are imported)"
    ) in captured.err


def test_grid_refuses_demos_of_the_other_arm(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--arm left with right-arm demonstrations filled the left arm's table
    from the right arm's reaches without a note; refused naming the arms."""
    path = tmp_path / "right.mcap"
    write_demos(path, synthesize(0, subjects=1, trials=1))
    assert main(["decide", "--grid", "--arm", "left", "--demos", str(path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert (
        f"{path}: its 16 reaches are of the right arm, none of the left arm the "
        "table is for (--arm left)"
    ) in captured.err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--target", "0.5", "-0.1", "0.05"], "m from the right shoulder"),
        (["--target", "0.12", "nan", "0.05"], "target[1] must be a finite number"),
        (
            ["--target", "0.12", "-0.1", "0.05", "--start", "9", "0", "0", "0", "0"],
            "RShoulderPitch",
        ),
        (["--target", "0.12", "-0.1", "0.05", "--palm", "0", "0", "0"], "zero vector"),
        (["--grid", "--plot", "grid.png"], "--plot is for one decision"),
        (["--grid", "--duration", "1"], "--duration is for one decision"),
        (["--grid", "--start", "0", "0", "0", "0.5", "0"], "--start is for one"),
        (["--grid", "--palm", "0", "0", "1"], "--palm is for one decision"),
        (["--target", "0.12", "-0.1", "0.05", "--demos", "d.mcap"], "--demos adds"),
        (["--target", "0.12", "-0.1", "0.05", "--plot", "decision"], "name a .png"),
        (
            ["--target", "0.12", "-0.1", "0.05", "--plot", "/absent/d.png"],
            "No such file",
        ),
    ],
)
def test_bad_input_is_a_clear_error(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Unreachable, NaN, out-of-range or zero inputs, options the form would
    ignore, a plot file matplotlib would rename: exit 1 and a named error."""
    assert main(["decide", *args]) == 1
    assert message in capsys.readouterr().err


def test_a_palm_of_huge_parts_is_the_same_direction(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """--palm 1e308 1e308 0 is the direction (1, 1, 0): the same decision (its
    length once overflowed and the palm became the zero vector)."""
    goal = ["--target", "0.12", "-0.1", "0.05", "--json"]
    outputs = []
    for palm in (["1e308", "1e308", "0"], ["1", "1", "0"]):
        assert main(["decide", *goal, "--palm", *palm]) == 0
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1]
    assert "W_PR" in outputs[0]


def test_a_wrist_path_starts_at_its_first_sample(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A still path 21 cm from the resting wrist: the arm starts on it, as
    ``armplan plan`` does (it once reported the wrist 212 mm from the goal).
    A path of one sample is refused, as by ``armplan plan``."""
    path = tmp_path / "still.csv"
    path.write_text("t,x,y,z\n0,0.15,-0.1,0.1\n0.01,0.15,-0.1,0.1\n")
    assert main(["decide", "--wrist-path", str(path)]) == 0
    assert "2 points; wrist 0.000 mm from the goal" in capsys.readouterr().out
    one = tmp_path / "one.csv"
    one.write_text("t,x,y,z\n0,0.15,-0.1,0.1\n")
    assert main(["decide", "--wrist-path", str(one)]) == 1
    assert f"at least 2 samples, {one} has 1" in capsys.readouterr().err
    assert main(["decide", "--wrist-path", str(path), "--duration", "1"]) == 1
    assert "--wrist-path keeps its own times" in capsys.readouterr().err


def test_bad_wrist_path_file(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A CSV without the header, or with decreasing times, names the problem."""
    path = tmp_path / "bad.csv"
    path.write_text("time,x,y,z\n0,0.1,-0.1,0\n")
    assert main(["decide", "--wrist-path", str(path)]) == 1
    assert "header t,x,y,z" in capsys.readouterr().err
    path.write_text("t,x,y,z\n0,0.1,-0.1,0\n0,0.1,-0.1,0\n")
    assert main(["decide", "--wrist-path", str(path)]) == 1
    assert "times must increase" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["decide", "plan"])
def test_a_wrist_path_file_from_t_1_is_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    """Times are from the movement's start: a CSV whose first t is 1.0 was
    planned as a trajectory starting at 1 s. Refused naming the line and what
    to do, by decide and plan alike."""
    path = tmp_path / "late.csv"
    path.write_text("t,x,y,z\n1.0,0.1,-0.1,0\n1.01,0.1,-0.1,0\n")
    assert main([command, "--wrist-path", str(path)]) == 1
    assert (
        f"{path}: line 2: the first t is 1 s, not 0: a wrist path's times are "
        "from the movement's start (the trajectory keeps them); subtract it "
        "from every t"
    ) in capsys.readouterr().err


def test_wrong_model_version_is_refused_without_traceback(
    tmp_path: pathlib.Path,
) -> None:
    """A model file of another version: exit 1, the version named, no traceback."""
    data = json.loads(default_model().to_json())
    data["version"] = 7
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data))
    out = armplan(
        "decide", "--target", "0.12", "-0.09", "0.05", "--model", str(path), "--json"
    )
    assert out.returncode == 1
    assert "Traceback" not in out.stderr
    assert "motion-model file version 7" in out.stderr
    assert json.loads(out.stdout)["error"]["kind"] == "model_file_error"


def test_a_given_model_file_is_used(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--model reads the file given."""
    path = tmp_path / "model.json"
    save_model(default_model(), path)
    assert (
        main(["decide", "--target", "0.12", "-0.09", "0.05", "--model", str(path)]) == 0
    )
    assert "primitive" in capsys.readouterr().out


@pytest.mark.parametrize("arm", ["right", "left"])
def test_a_targets_decision_lasts_as_long_as_the_plan(
    arm: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Without --duration the reach is as long as ``armplan plan`` plays it
    (the planner's human pace, 0.69 s here: 70 points at 100 Hz), not a
    fixed 0.8 s; --duration still sets it."""
    goal = ["0.12", "-0.13" if arm == "right" else "0.13", "0.05"]
    assert main(["plan", "--arm", arm, "--target", *goal, "--json"]) == 0
    played = json.loads(capsys.readouterr().out)["times"]
    assert main(["decide", "--arm", arm, "--target", *goal, "--json"]) == 0
    decision = parse(Decision, capsys.readouterr().out)
    assert len(decision.times) == len(played) == 70
    assert decision.times[-1] == pytest.approx(played[-1] - played[0], abs=1e-9)
    given = ["decide", "--arm", arm, "--target", *goal, "--duration", "1"]
    assert main([*given, "--json"]) == 0
    assert parse(Decision, capsys.readouterr().out).times[-1] == pytest.approx(1.0)
