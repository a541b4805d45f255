"""A timed wrist path from a CSV file (``armplan decide --wrist-path``).

The format (the same as ``armplan plan --wrist-path``): a header row
``t,x,y,z``, then one row per point: time [s], strictly increasing, and the
wrist position in NAO's torso frame [m]. Times are from the movement's start:
the first row's t is 0 (the trajectory keeps the path's times).
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from shared.errors import InvalidInputError
from shared.input_files import read_at_most
from shared.messages import WristPath, parse
from shared.messages.wrist_path import too_few_samples
from shared.robot.side import Side

HEADER = ["t", "x", "y", "z"]


def read_wrist_csv(path: str | Path, arm: Side | str = Side.RIGHT) -> WristPath:
    """The wrist path in ``path``, validated.

    Raises:
        InvalidInputError: naming the file, and the line or field that is
            wrong (missing file, wrong header, a cell that is not a number or
            not finite, no samples or only one, a first time other than 0, times that do
            not increase, too many points).
    """
    path = Path(path)
    try:
        rows = _rows(path)
    except OSError as exc:
        raise InvalidInputError(
            f"{path}: cannot read the wrist path ({exc.strerror})", field="wrist_path"
        ) from None
    except (csv.Error, UnicodeDecodeError) as exc:
        raise InvalidInputError(
            f"{path}: not a CSV file ({exc})", field="wrist_path"
        ) from None
    if not rows or [c.strip().lower() for c in rows[0][1]] != HEADER:
        raise InvalidInputError(
            f"{path}: the first row must be the header t,x,y,z", field="wrist_path"
        )
    times: list[float] = []
    positions = []
    before = 0
    for line, row in rows[1:]:
        if not times and (first := _numbers(row, path, line)[0]) != 0.0:
            raise InvalidInputError(
                f"{path}: line {line}: the first t is {first:.9g} s, not 0: a "
                "wrist path's times are from the movement's start (the "
                "trajectory keeps them); subtract it from every t",
                field="times",
            )
        values = _numbers(row, path, line)
        if times and not values[0] > times[-1]:
            raise InvalidInputError(
                f"{path}: line {line}: times must increase: t = {values[0]:g} s "
                f"is not after t = {times[-1]:g} s on line {before}",
                field="wrist_path",
            )
        times.append(values[0])
        positions.append(values[1:])
        before = line
    if not times:
        raise InvalidInputError(
            f"{path}: the wrist path is empty: no samples after the header",
            field="wrist_path",
        )
    if problem := too_few_samples(len(times), str(path)):
        raise InvalidInputError(problem, field="wrist_path")
    try:
        return parse(
            WristPath, {"arm": Side.parse(arm), "times": times, "positions": positions}
        )
    except InvalidInputError as exc:
        raise InvalidInputError(f"{path}: {exc.message}", field=exc.field) from None


def _rows(path: Path) -> list[tuple[int, list[str]]]:
    """The file's non-blank rows, each with the line it starts on (from 1)."""
    rows = []
    text = read_at_most(path).decode("utf-8-sig")  # Excel writes a BOM
    reader = csv.reader(io.StringIO(text, newline=""))
    start = 1
    for row in reader:
        if row:
            rows.append((start, row))
        start = reader.line_num + 1
    return rows


def _numbers(row: list[str], path: Path, line: int) -> list[float]:
    if len(row) != 4:
        raise InvalidInputError(
            f"{path}: line {line} has {len(row)} cells, expected 4 (t,x,y,z)",
            field="wrist_path",
        )
    try:
        values = [float(cell) for cell in row]
    except ValueError:
        raise InvalidInputError(
            f"{path}: line {line} holds a cell that is not a number: {row}",
            field="wrist_path",
        ) from None
    for name, value in zip(HEADER, values, strict=True):
        if not math.isfinite(value):
            raise InvalidInputError(
                f"{path}: line {line}: {name} = {value} is not a finite number",
                field="wrist_path",
            )
    return values
