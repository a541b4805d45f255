"""A goal NAO cannot reach after retargeting: a note at import, and the
similarity experiment's error names the file, subject and trial, with the
subject's palm (--palm) too. A reach left out for the palm's sake is
counted in the tables, and a run left with none is an error."""

from __future__ import annotations

import csv
import json
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from armplan.experiments.markdown_table import markdown_tables
from armplan.experiments.similarity import Skipped, check_some_left, run_similarity
from armplan.experiments.similarity_report import tables
from armplan.experiments.similarity_summary import summary
from shared.demos import read_demos
from shared.errors import InvalidInputError, UnreachableTargetError
from tests.test_demos_input_csv import arm_rows, write_csv


def _to_mouth(n: int = 101) -> list[list[str]]:
    """A hand-to-mouth reach in 1 s: the elbow bends from 6 to 145 deg, the
    upper arm hanging a little forward (upper arm 0.3 m, forearm 0.25 m)."""
    s = np.linspace(0.0, 1.0, n)
    progress = 10 * s**3 - 15 * s**4 + 6 * s**5
    bend = np.radians(6.0 + 139.0 * progress)
    upper = np.array([0.1, -0.1, -1.0]) / np.linalg.norm([0.1, -0.1, -1.0])
    across = np.cross(upper, [0.0, 1.0, 0.0])
    across /= np.linalg.norm(across)
    shoulder = np.array([0.1, -0.2, 1.4])
    elbow = shoulder + 0.3 * upper
    fore = np.cos(bend)[:, None] * upper + np.sin(bend)[:, None] * across
    wrist = elbow + 0.25 * fore
    rows = []
    for k in range(n):
        cells = [f"{k / 100:.2f}", "0"]
        cells += [f"{v:.6f}" for p in (shoulder, elbow, wrist[k]) for v in p]
        rows.append(cells)
    return rows


def _import(tmp_path: pathlib.Path, rows: list[list[str]]) -> tuple[int, pathlib.Path]:
    path = write_csv(tmp_path / "mouth.csv", rows)
    markers = tmp_path / "map.json"
    markers.write_text(
        json.dumps({"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"})
    )
    out = tmp_path / "mouth.mcap"
    argv = ["demos", "import", str(path), "--markers", str(markers), "-o", str(out)]
    return main(argv), out


def test_a_goal_out_of_naos_reach_is_noted_and_named_by_the_experiment(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The human elbow bent 145 deg (NAO's stops at 88.5): imported silently,
    and the experiment failed naming only the target."""
    code, out = _import(tmp_path, _to_mouth())
    assert code == 0
    assert capsys.readouterr().err == (
        f"armplan: note: {tmp_path / 'mouth.csv'}: subject 'mouth', trial 0 (lines "
        "2-102): its goal, retargeted, is 0.0683 m from NAO's right shoulder, "
        "45.8 mm nearer than NAO's wrist reaches (0.1141..0.1617 m; the subject's "
        "elbow is bent 145 deg there, NAO's ElbowRoll 2.0 to 88.5 deg): armplan "
        "fit can use the trial, but NAO cannot reach its goal, and armplan "
        "experiment similarity refuses it\n"
    )
    with pytest.raises(UnreachableTargetError) as caught:
        run_similarity(read_demos(out), samples=11)
    assert caught.value.message.startswith(
        f"{out}: subject 'mouth', trial 0 (off the grid), wrist-path sample 59 "
        "(t = 0.590 s): target ("
    )
    assert caught.value.message.endswith(
        "NAO cannot make this reach (armplan demos import notes a goal out of "
        "NAO's reach); import the demonstrations without it"
    )


def test_a_goal_within_reach_gets_no_note(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, _ = _import(tmp_path, arm_rows(0))
    assert code == 0
    assert capsys.readouterr().err == ""


def test_a_straight_arm_is_just_out_of_naos_reach(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """NAO's elbow never straightens fully (ElbowRoll from 2 deg): a goal with
    the human arm straight is 0.3 mm beyond it, and the planner refuses it."""
    rows = arm_rows(0)
    for row in rows:  # the wrist on the upper arm's line, 0.25 m past the elbow
        shoulder, elbow = np.array(row[2:5], float), np.array(row[5:8], float)
        wrist = elbow + 0.25 * (elbow - shoulder) / 0.3
        row[8:11] = [f"{v:.6f}" for v in wrist]
    code, _ = _import(tmp_path, rows)
    assert code == 0
    assert "0.3 mm farther than NAO's wrist reaches (0.1141..0.1617 m; the " in (
        capsys.readouterr().err
    )


def _thumbed(path: pathlib.Path, rows: list[list[str]]) -> pathlib.Path:
    """Import ``rows`` with a thumb-side marker 4 cm across the forearm (so
    the palm is known); the demonstration file written."""
    header = ["time", "trial"]
    header += [f"{m}_{a}" for m in ("RSHO", "RELB", "RWRB", "RWRA") for a in "xyz"]
    lines = []
    for row in rows:
        elbow, wrist = np.array(row[5:8], float), np.array(row[8:11], float)
        across = np.cross(wrist - elbow, [0.0, 1.0, 0.0])
        thumb = wrist + 0.04 * across / np.linalg.norm(across)
        lines.append([*row, *(f"{v:.6f}" for v in thumb)])
    table = path.with_suffix(".csv")
    with open(table, "w", newline="") as stream:
        csv.writer(stream).writerows([header, *lines])
    markers = path.with_name(f"{path.stem}-map.json")
    names = {"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB", "thumb": "RWRA"}
    markers.write_text(json.dumps({**names, "subject": path.stem}))
    argv = ["demos", "import", str(table), "--markers", str(markers), "-o", str(path)]
    assert main(argv) == 0
    return path


def test_with_the_palm_too_a_goal_out_of_naos_reach_fails_the_run(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The goal is out of reach whatever the palm: --palm left the reach out
    and, with nothing left, crashed with an IndexError; beside a good reach
    it passed, saying nothing. Now it fails as without --palm, naming it."""
    mouth = _thumbed(tmp_path / "mouth.mcap", _to_mouth())
    capsys.readouterr()
    out = tmp_path / "results"
    argv = ["experiment", "similarity", "--demos", str(mouth), "--palm"]
    code = main([*argv, "--samples", "11", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 1
    assert err.startswith(
        f"armplan: error: {mouth}: subject 'mouth', trial 0 (off the grid), "
        "wrist-path sample 59 (t = 0.590 s): target ("
    )
    assert "import the demonstrations without it" in err
    assert not out.exists() or list(out.iterdir()) == []
    good = _thumbed(tmp_path / "good.mcap", arm_rows(0))
    with pytest.raises(UnreachableTargetError, match="subject 'mouth'"):
        run_similarity(read_demos([good, mouth]), samples=11, palm=True)


def test_reaches_left_out_for_the_palm_are_counted_in_the_tables(
    tmp_path: pathlib.Path,
) -> None:
    """A reach whose palm the planner cannot meet is left out; the tables said
    "reaches 1", bars met, and nothing of it (only the JSON listed it)."""
    good = _thumbed(tmp_path / "good.mcap", arm_rows(0))
    rows = run_similarity(read_demos([good]), samples=11, palm=True)
    assert {r.method.value: r.posture_similarity is not None for r in rows} == {
        "mp": True,
        "least-norm": True,
        "single": True,
    }
    left = Skipped("P02", 0, "the IK solver stopped 9.0 mm from it", "right", 3, "b")
    numbers = summary(
        rows, {"path": "human", "palm": True, "skipped": [left._asdict()]}
    )
    shown = tables(numbers)
    title = "left out: 1 reach (no posture within the limits meets the subject's palm)"
    assert list(shown)[:2] == ["overall", title]
    assert shown[title] == (["reach", "why"], [["b", left.reason]])
    assert f"**{title}**" in markdown_tables(shown)
    assert not any(t.startswith("left out") for t in tables(summary(rows, {})))


def test_a_run_with_every_reach_left_out_for_the_palm_is_an_error() -> None:
    """Nothing to compare: a typed error naming how many and the first, not
    an IndexError in the tables."""
    left = [Skipped("P02", 0, "stopped 9.0 mm from it", "right", 3, "b.mcap: P02")]
    with pytest.raises(InvalidInputError) as caught:
        check_some_left([], left)
    assert caught.value.message == (
        "with --palm no reach is left to compare: the planner met the subject's "
        "palm in none of the 1 reach (b.mcap: P02: stopped 9.0 mm from it); run "
        "without --palm"
    )
    assert caught.value.evidence["skipped"][0]["trial"] == 3
    check_some_left([], [])  # no reach left out: nothing to say
