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
    rows = _held(60.0)
    code, out = _import(tmp_path, rows)
    assert code == 1
    times = [row[0] for row in rows]  # line k + 2 holds rows[k]
    moves, arrives, last = (
        2 + times.index("0.01"),
        2 + times.index("0.29"),
        1 + len(rows),
    )
    assert capsys.readouterr().err == (
        f"armplan: error: {tmp_path / 'rec.csv'}: trial 0 of subject 'rec' (lines "
        f"2-{last}) lasts 60.3 s, its wrist still for 60.0 s at its goal, lines "
        f"{arrives}-{last} (at most 3 s; the wrist moves from 0.01 s (line {moves}) "
        f"to 0.29 s (line {arrives})): a trial must be one reach, from its start "
        "to its goal, and armplan fit would count the stillness as reaching. Crop "
        "it to the reach, or give --allow-long to import it as it is\n"
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


def _still(seconds: float) -> list[list[str]]:
    """The arm held at the swing's start for ``seconds`` (a calibration take)."""
    first = arm_rows(0)[0]
    return [[f"{k / 100:.2f}", *first[1:]] for k in range(round(100 * seconds))]


@pytest.mark.parametrize("more", [(), ("--allow-long",)], ids=["plain", "allow-long"])
def test_a_still_take_is_no_reach_and_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], more: tuple[str, ...]
) -> None:
    """A 2 s take with the arm held (a static calibration take) passed, being
    under 3 s still: 8 beside 16 reaches doubled every rate of the fit.
    ``--allow-long`` does not let it in: it is no reach at all."""
    rows = _still(2.0)
    code, out = _import(tmp_path, rows, *more)
    assert code == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {tmp_path / 'rec.csv'}: trial 0 of subject 'rec' (lines "
        f"2-{len(rows) + 1}) lasts 1.99 s, and its wrist ends 0.0 mm from where "
        "it starts (a reach goes at least 16.2 mm, 0.1 of NAO's arm): a still "
        "take (e.g. a calibration) or a hand shifting, not a reach. A trial must "
        "be one reach, from its start to its goal: leave this one out\n"
    )
    assert not out.exists()


@pytest.mark.parametrize(("frames", "refused"), [(2, True), (11, True), (13, False)])
def test_a_trial_moving_under_a_tenth_of_a_second_is_refused(
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
    frames: int,
    refused: bool,
) -> None:
    """16 two-frame (10 ms) trials passed import and fit and gave a
    one-primitive model; a wrist moving for 0.09 s is refused, 0.11 s not."""
    code, _ = _import(tmp_path, arm_rows(0, n=frames))
    assert code == int(refused)
    err = capsys.readouterr().err
    assert ("far more briefly than a person reaches (at least 0.1 s" in err) is (
        refused
    )
    if frames == 2:
        assert "(lines 2-3) lasts 0.01 s, and its wrist moves for 0.00 s (from " in err
        assert "(from 0.01 s (line 3) to 0.01 s (line 3))" in err


def test_a_csv_trial_is_refused_by_its_own_number(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Trial 15 of the file, after trial 3, still for a minute: the error
    names trial 15, as the file and its gap notes do (it named the trial's
    new number, 101 with --first-trial 100)."""
    long = [[row[0], "15", *row[2:]] for row in _held(60.0)]
    code, _ = _import(tmp_path, arm_rows(3) + long, "--first-trial", "100")
    assert code == 1
    err = capsys.readouterr().err
    first, last = 2 + 30, 1 + 30 + len(long)  # line k + 2 holds rows[k]
    assert (
        f"{tmp_path / 'rec.csv'}: trial 15 of subject 'rec' (lines {first}-{last}) "
        "lasts 60.3 s"
    ) in err
