"""A goal NAO cannot reach after retargeting: a note at import, and the
similarity experiment's error names the file, subject and trial."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from armplan.experiments.similarity import run_similarity
from shared.demos import read_demos
from shared.errors import UnreachableTargetError
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
        f"{out}: subject 'mouth', trial 0 (off the grid): target ("
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
