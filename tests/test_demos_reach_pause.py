"""A trial whose wrist stops on its way between two movements is two reaches."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from shared.demos import read_demos, synthesize
from shared.demos.reach_span import long_trial_problem
from tests.test_demos_input_csv import BEND, write_csv

#: Sample rate [Hz] and marker noise [m] (a standard deviation per coordinate).
RATE, NOISE = 100.0, 0.0005


def _minimum_jerk(times: np.ndarray, start: float, span: float) -> np.ndarray:
    """0 before ``start`` [s], 1 after ``start + span``, minimum jerk between."""
    s = np.clip((times - start) / span, 0.0, 1.0)
    return 10 * s**3 - 15 * s**4 + 6 * s**5


def _two_moves(stop: float, share: float = 0.5) -> list[list[str]]:
    """Rows of an arm swinging 1.2 rad in two 0.6 s moves, ``stop`` [s] apart.

    0.3 s of rest, the first move (``share`` of the way), ``stop`` still,
    the second move, 0.3 s of hold; seeded marker noise.
    """
    second = 0.9 + stop
    times = np.arange(round((second + 0.9) * RATE)) / RATE
    angle = 1.2 * (
        share * _minimum_jerk(times, 0.3, 0.6)
        + (1 - share) * _minimum_jerk(times, second, 0.6)
    )
    n = len(times)
    shoulder = np.tile([0.1, -0.2, 1.4], (n, 1))
    down = np.stack((np.sin(angle), np.zeros(n), -np.cos(angle)), axis=1)
    fore = np.stack((np.sin(angle + BEND), np.zeros(n), -np.cos(angle + BEND)), 1)
    elbow = shoulder + 0.3 * down
    wrist = elbow + 0.25 * fore
    noise = np.random.default_rng(5).normal(0.0, NOISE, (3, n, 3))
    points = (shoulder + noise[0], elbow + noise[1], wrist + noise[2])
    return [
        [f"{times[k]:.2f}", "0", *(f"{v:.6f}" for p in points for v in p[k])]
        for k in range(n)
    ]


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


def test_two_reaches_with_a_hold_between_are_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A reach, 0.8 s still, a second reach: imported as one trial, it made
    the fit's W_R rate 2.80 /rad instead of about 5.7."""
    rows = _two_moves(0.8)
    code, out = _import(tmp_path, rows)
    assert code == 1
    times = [row[0] for row in rows]  # line k + 2 holds rows[k]
    stops, restarts = 2 + times.index("0.81"), 2 + times.index("1.79")
    assert capsys.readouterr().err == (
        f"armplan: error: {tmp_path / 'rec.csv'}: trial 0 of subject 'rec' (lines "
        f"2-{len(rows) + 1}) lasts 2.6 s, and its wrist stops on its way for 0.98 "
        f"s, from 0.81 s (line {stops}) to 1.79 s (line {restarts}), 94.4 mm from "
        "its start and 96.5 mm from its goal (a reach stops for under 0.5 s on its "
        "way): two reaches, not one; split the trial where the wrist stops (0.81 "
        f"s, line {stops}) and restarts (1.79 s, line {restarts}). Crop it to the "
        "reach, or give --allow-long to import it as it is\n"
    )
    assert not out.exists()


def test_allow_long_imports_two_reaches_with_a_note(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--allow-long`` keeps such a trial as it is, with a note."""
    code, out = _import(tmp_path, _two_moves(0.8), "--allow-long")
    assert code == 0
    err = capsys.readouterr().err
    assert "stops on its way for 0.98 s" in err
    assert "imported as it is (--allow-long)" in err
    assert len(read_demos(out).trials) == 1


@pytest.mark.parametrize(
    ("stop", "share"),
    [(0.0, 0.5), (0.2, 0.5), (1.0, 0.97)],
    ids=["slows-to-a-standstill", "stops-briefly", "stops-near-the-goal"],
)
def test_a_reach_that_slows_on_its_way_is_one_reach(
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
    stop: float,
    share: float,
) -> None:
    """Two moves that meet at rest, a 0.2 s stop, or a stop 3 % of the way
    short of the goal (the reach's own end) pass silently."""
    code, _ = _import(tmp_path, _two_moves(stop, share))
    assert code == 0
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("rate", [100.0, 250.0])
def test_no_synthetic_reach_is_taken_for_two(rate: float) -> None:
    """The synthetic set's reaches (``armplan demos synth``) all pass."""
    demos = synthesize(0, subjects=2, trials=1, rate=rate)
    assert [t.trial for t in demos.trials if long_trial_problem(t)] == []
