"""A CSV file of marker tracks as a table: its header, its rows by trial, its cells.

The reading half of ``csv_import``: the file's rows with their line numbers
(blank lines skipped, an Excel byte order mark read), the column of each
needed name, each trial's rows (the ``trial`` column, its rows
consecutive) and each cell as a number, every refusal naming the file's
line and column. What the numbers mean (times, markers, trials) is
``csv_import``'s.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import NamedTuple

from shared.demos.markers import MarkerMap
from shared.errors import DemoFileError


class Row(NamedTuple):
    """One data row: its line in the file (from 1) and its cells."""

    line: int
    cells: list[str]


def read_table(path: Path) -> tuple[list[str], list[Row]]:
    """The header and the non-blank data rows, each with its line."""
    table: list[Row] = []
    try:
        with open(path, newline="", encoding="utf-8-sig") as stream:  # Excel: BOM
            reader = csv.reader(stream)
            start = 1
            for cells in reader:
                if cells:
                    table.append(Row(start, cells))
                start = reader.line_num + 1
    except OSError as exc:
        raise DemoFileError(str(path), f"cannot read it: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise DemoFileError(str(path), _not_text(path, exc.start)) from None
    except csv.Error as exc:
        raise DemoFileError(str(path), f"not a CSV file ({exc})") from None
    if len(table) < 2:
        raise DemoFileError(str(path), "needs a header row and at least one data row")
    return [h.strip() for h in table[0].cells], table[1:]


#: A C3D file's second byte (``c3d_layout.KEY``).
C3D_KEY = 0x50


def _not_text(path: Path, byte: int) -> str:
    """Why a file that is not UTF-8 from ``byte`` on is no CSV file.

    A C3D file named .csv was "not a CSV file ('utf-8' codec can't decode
    byte 0x80 in position 14: invalid start byte)".
    """
    with open(path, "rb") as stream:
        start = stream.read(2)
    if len(start) == 2 and start[0] >= 2 and start[1] == C3D_KEY:
        return "not a CSV file: it is a C3D file (binary); name it .c3d to import it"
    return (
        f"not a CSV file: byte {byte} is not UTF-8 text; save the CSV as UTF-8 "
        "(or it is not a CSV file)"
    )


def columns_of(
    header: list[str], markers: MarkerMap, path: str
) -> dict[str, list[int]]:
    """Column indices: ``time`` and the x, y, z of each mapped marker."""
    wanted = {"time": ["time"]}
    for role, name in markers.names.items():
        wanted[role] = [f"{name}_{axis}" for axis in "xyz"]
    needed = [c for cols in wanted.values() for c in cols]
    missing = [c for c in needed if c not in header]
    if missing:
        raise DemoFileError(
            path,
            f"lacks the column{'s' if len(missing) > 1 else ''} "
            f"{', '.join(missing)}{header_read(header)}",
            missing=missing,
        )
    for column in [*needed, "trial"]:
        if header.count(column) > 1:
            raise DemoFileError(
                path, f"the header names column {column!r} more than once"
            )
    return {role: [header.index(c) for c in cols] for role, cols in wanted.items()}


#: Delimiters a spreadsheet may write instead of commas, named for messages.
OTHER_DELIMITERS = {";": "semicolons", "\t": "tabs"}
#: How many header cells, and characters of each, a message shows.
_SHOWN_CELLS, _SHOWN_CHARS = 6, 40


def header_read(header: list[str]) -> str:
    """The header as read, for a message, and a hint if its delimiter is wrong.

    A tab- or semicolon-separated file reads as one column: the hint says so
    (``"; its header reads 1 column: 'time;trial;RS...': ..."``).
    """
    cells = [h if len(h) <= _SHOWN_CHARS else h[:_SHOWN_CHARS] + "..." for h in header]
    shown = ", ".join(repr(c) for c in cells[:_SHOWN_CELLS])
    if len(header) > _SHOWN_CELLS:
        shown += ", ..."
    text = f"; its header reads {len(header)} column{'s' * (len(header) > 1)}: {shown}"
    for mark, name in OTHER_DELIMITERS.items():
        if any(mark in h for h in header):
            return (
                f"{text}: its columns seem separated by {name}; the format's are "
                "separated by commas, with points for decimals (export it as "
                "comma-separated values)"
            )
    return text


def trial_rows(rows: list[Row], header: list[str], path: str) -> dict[int, list[Row]]:
    """The rows of each trial, in file order (all in trial 0 without ``trial``)."""
    if "trial" not in header:
        return {0: rows}
    index = header.index("trial")
    groups: dict[int, list[Row]] = {}
    last: int | None = None
    for row in rows:
        key = _trial_number(cell(row, index, header, path), row.line, path)
        if key in groups and key != last:
            raise DemoFileError(
                path,
                f"line {row.line}: the rows of trial {key} are not consecutive",
                line=row.line,
            )
        groups.setdefault(key, []).append(row)
        last = key
    return groups


def _trial_number(text: str, line: int, path: str) -> int:
    """The trial number in a ``trial`` cell: a whole number from 0 (``3``, ``3.0``)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value != round(value) or value < 0:
        shown = "an empty cell" if not text else repr(text)
        raise DemoFileError(
            path,
            f"line {line}, column 'trial' holds {shown}, which is not a trial "
            "number (a whole number from 0)",
            line=line,
            column="trial",
            value=text,
        )
    return int(text) if text.isdigit() else int(value)


def cell(row: Row, index: int, header: list[str], path: str) -> str:
    """The stripped cell ``index`` of ``row``; refuse a row too short for it."""
    if index >= len(row.cells):
        raise DemoFileError(
            path,
            f"line {row.line} has {len(row.cells)} cells, the header "
            f"{len(header)}: it lacks column {header[index]!r} (leave a cell "
            "empty for a missing sample)",
            line=row.line,
            column=header[index],
        )
    return row.cells[index].strip()


def number(text: str, line: int, column: str, path: str) -> float:
    """A cell's number; an empty cell or ``nan`` is a missing sample (NaN)."""
    if not text:
        return math.nan
    try:
        value = float(text)
    except ValueError:
        raise DemoFileError(
            path,
            f"line {line}, column {column!r} holds {text!r}, which is not a number",
            line=line,
            column=column,
            value=text,
        ) from None
    if math.isinf(value):
        raise DemoFileError(
            path,
            f"line {line}, column {column!r} holds {text!r}, which is not a "
            "finite number",
            line=line,
            column=column,
            value=text,
        )
    return value
