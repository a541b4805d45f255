"""A marker map whose names say the other arm: refused without ``arm``, noted with.

The names are read as labs write them (Plug-in Gait's ``LSHO``, ``L_Elbow``,
``wrist.L``, a C3D label's ``Subject:`` prefix); names that say no side, or
not all the same one, say nothing.
"""

from __future__ import annotations

import csv
import json
import pathlib

import pytest

from armplan.cli.main import main
from shared.demos import read_demos
from shared.demos.marker_side import named_side, other_side_named
from shared.robot.side import Side
from tests.test_demos_input_csv import arm_rows

LEFT = {"shoulder": "LSHO", "elbow": "LELB", "wrist": "LWRB"}


@pytest.mark.parametrize(
    ("names", "side"),
    [
        (["LSHO", "LELB", "LWRB"], Side.LEFT),
        (["RSHO", "RELB", "RWRA"], Side.RIGHT),
        (["L_Shoulder", "L_Elbow", "L_Wrist"], Side.LEFT),
        (["LeftShoulder", "LEFT_ELBOW", "left wrist"], Side.LEFT),
        (["shoulder.R", "elbow_r", "Wrist-Right"], Side.RIGHT),
        (["P01:LSHO", "P01:LELB", "P01:LWRB"], Side.LEFT),
        (["l_sho", "l_elb", "l_wri"], Side.LEFT),
        (["RSHO", "LELB", "RWRB"], None),  # not all one side
        (["SHO", "ELB", "WRB"], None),  # no side at all
        (["Radius", "lateral", "Lx"], None),  # a letter before lower case
        (["LSHO", "LELB", "WRB"], None),  # one says none
    ],
)
def test_the_side_every_name_says(names: list[str], side: Side | None) -> None:
    assert named_side(names) is side


def test_only_the_other_side_is_named() -> None:
    assert other_side_named(LEFT, Side.LEFT) is None
    said = other_side_named(LEFT, Side.RIGHT)
    assert said == "the markers (LSHO, LELB, LWRB) are named like the left arm's"
    assert (
        other_side_named({"shoulder": "A", "elbow": "B", "wrist": "C"}, Side.RIGHT)
        is None
    )


def _capture(tmp_path: pathlib.Path) -> pathlib.Path:
    """A CSV of one reach whose columns are named like the left arm's markers."""
    header = ["time", "trial"] + [f"{m}_{a}" for m in LEFT.values() for a in "xyz"]
    path = tmp_path / "mocap.csv"
    with open(path, "w", newline="") as stream:
        csv.writer(stream).writerows([header, *arm_rows(0)])
    return path


def _import(
    tmp_path: pathlib.Path, markers: dict[str, str]
) -> tuple[int, pathlib.Path]:
    map_path = tmp_path / "map.json"
    map_path.write_text(json.dumps(markers))
    out = tmp_path / "out.mcap"
    args = ["demos", "import", "--markers", str(map_path), "-o", str(out)]
    return main([*args, str(_capture(tmp_path))]), out


def test_left_markers_without_an_arm_are_refused_and_nothing_written(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out = _import(tmp_path, LEFT)
    assert code == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {tmp_path / 'map.json'}: the markers (LSHO, LELB, LWRB) "
        'are named like the left arm\'s, but the map gives no "arm", which means '
        'the right arm: give "arm": "left" if they are the left arm\'s (or "arm": '
        '"right" if they are not)\n'
    )
    assert not out.exists()


@pytest.mark.parametrize("arm", ["left", "right"])
def test_a_given_arm_is_taken_at_its_word(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], arm: str
) -> None:
    """The map's own arm is imported; names that contradict it get a note."""
    code, out = _import(tmp_path, {**LEFT, "arm": arm})
    assert code == 0
    captured = capsys.readouterr()
    assert f"retargeted to NAO's {arm} arm\n" in captured.out
    note = "are named like the left arm's, but the map's \"arm\" is right"
    assert (note in captured.err) is (arm == "right")
    assert {t.arm for t in read_demos(out).trials} == {Side(arm)}
