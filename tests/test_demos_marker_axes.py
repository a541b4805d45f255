"""A marker map's axes must turn the capture, never mirror it.

``["-z", "x", "y"]`` (determinant -1) was accepted: the import read a right
arm as its mirror image, and only the fit's "0.0 % explained" showed it.
"""

from __future__ import annotations

import itertools
import json
import math
import pathlib

import pytest

from shared.demos.markers import MarkerMap, read_marker_map
from shared.errors import DemoFileError, InvalidInputError
from shared.messages.base import parse

ROLES = {"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"}


def _signed_permutations() -> list[tuple[list[str], int]]:
    """All 48 axes maps, each with its determinant: the signs' product times
    the permutation's parity (-1 per pair out of order)."""
    found = []
    for order in itertools.permutations("xyz"):
        swaps = sum(a > b for a, b in itertools.combinations(order, 2))
        for signs in itertools.product((1, -1), repeat=3):
            axes = [
                ("-" if s < 0 else "") + a for a, s in zip(order, signs, strict=True)
            ]
            found.append((axes, (-1) ** swaps * math.prod(signs)))
    return found


def test_rotations_pass_and_mirrors_are_refused() -> None:
    """The 24 rotations are accepted, the 24 reflections refused."""
    maps = _signed_permutations()
    assert sorted(det for _, det in maps) == [-1] * 24 + [1] * 24
    for axes, det in maps:
        if det > 0:
            assert parse(MarkerMap, {**ROLES, "axes": axes}).axes == tuple(axes)
            continue
        with pytest.raises(InvalidInputError) as info:
            parse(MarkerMap, {**ROLES, "axes": axes})
        assert info.value.field == "axes"
        assert f"axes {axes} mirror the capture" in info.value.message


def test_a_mirroring_map_file_is_refused_naming_it(tmp_path: pathlib.Path) -> None:
    """The hunt's map for a Y-up capture facing -z, with the left axis's sign
    lost: refused, naming the file and how to fix it; the right one reads."""
    path = tmp_path / "map.json"
    path.write_text(json.dumps({**ROLES, "axes": ["-z", "x", "y"]}))
    with pytest.raises(DemoFileError) as info:
        read_marker_map(path)
    assert info.value.message.startswith(
        f"{path}: invalid MarkerMap: axes: axes ['-z', 'x', 'y'] mirror the "
        "capture (determinant -1): a right arm would read as a left one"
    )
    assert "flip the sign of the one axis that is wrong" in info.value.message
    path.write_text(json.dumps({**ROLES, "axes": ["-z", "-x", "y"]}))
    assert read_marker_map(path).axes == ("-z", "-x", "y")


def test_an_unknown_axis_is_quoted_once(tmp_path: pathlib.Path) -> None:
    """The axes check quotes what it got; the error no longer adds the same
    value again ("got ('-z', '-x', 'w') (got ['-z', '-x', 'w'])")."""
    path = tmp_path / "map.json"
    path.write_text(json.dumps({**ROLES, "axes": ["-z", "-x", "w"]}))
    with pytest.raises(DemoFileError) as caught:
        read_marker_map(path)
    message = caught.value.message
    assert message.endswith("got ('-z', '-x', 'w')"), message
    assert message.count("got ") == 1, message
