"""demos import refuses a trial that is not one reach, unless told to keep it."""

from __future__ import annotations

import json
import pathlib

import pytest

from armplan.cli.main import main
from shared.demos import read_demos
from tests.test_demos_input_csv import arm_rows, write_csv


def _held(seconds: float) -> list[list[str]]:
    """One swing of the arm (0.29 s at 100 Hz), then ``seconds`` still at its end."""
    rows = arm_rows(0)
    last = rows[-1]
    for k in range(1, round(100 * seconds) + 1):
        rows.append([f"{float(last[0]) + k / 100:.2f}", *last[1:]])
    return rows


def _rest_swing_hold(rest: float, hold: float) -> list[list[str]]:
    """``rest`` [s] still at the swing's start, the swing, ``hold`` [s] still."""
    rows = _held(hold)
    first, steps = rows[0], round(100 * rest)
    lead = [[f"{k / 100:.2f}", *first[1:]] for k in range(steps)]
    shifted = [[f"{float(r[0]) + rest:.2f}", *r[1:]] for r in rows]
    return lead + shifted


def _import(
    tmp_path: pathlib.Path, rows: list[list[str]], *more: str
) -> tuple[int, pathlib.Path]:
    path = write_csv(tmp_path / "rec.csv", rows)
    markers = tmp_path / "map.json"
    markers.write_text(
        json.dumps({"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"})
    )
    out = tmp_path / "rec.mcap"
    argv = ["demos", "import", str(path), "--markers", str(markers)]
    return main([*argv, "-o", str(out), *more]), out


def test_a_reach_then_minutes_still_is_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A reach and then 60 s still was imported as one trial, and the fit made
    a model of the stillness."""
    code, out = _import(tmp_path, _held(60.0))
    assert code == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {tmp_path / 'rec.csv'}: trial 0 of subject 'rec' lasts "
        "60.3 s, its wrist still for 60.0 s at its goal (at most 3 s; the wrist "
        "moves from 0.01 s to 0.29 s): a trial must be one reach, from its start "
        "to its "
        "goal, and armplan fit would count the stillness as reaching. Crop it "
        "to the reach, or give --allow-long to import it as it is\n"
    )
    assert not out.exists()


def test_allow_long_imports_it_with_a_note(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out = _import(tmp_path, _held(60.0), "--allow-long")
    assert code == 0
    assert "imported as it is (--allow-long)" in capsys.readouterr().err
    assert len(read_demos(out).trials[0].times) == 30 + 6000


def test_a_reach_with_a_short_hold_is_one_reach(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """1.5 s still at the goal (a hold the capture keeps) passes silently."""
    code, _ = _import(tmp_path, _held(1.5))
    assert code == 0
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(("rest", "hold"), [(1.0, 1.0), (1.0, 2.0), (2.5, 2.5)])
def test_a_rest_before_and_a_hold_after_are_judged_apart(
    tmp_path: pathlib.Path, rest: float, hold: float
) -> None:
    """A capture's rest before the reach and its hold at the goal, each under
    3 s, pass: judged together (with the reach's own slow ends), 1 s of each
    was refused as 'still for most of it'."""
    code, out = _import(tmp_path, _rest_swing_hold(rest, hold))
    assert code == 0
    assert len(read_demos(out).trials) == 1


def test_a_trial_far_longer_than_a_reach_is_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """12 s of an arm swinging on: more than one reach."""
    code, _ = _import(tmp_path, arm_rows(0, n=1200))
    assert code == 1
    assert "lasts 12.0 s, far longer than a reach (at most 10 s; the wrist moves" in (
        capsys.readouterr().err
    )
