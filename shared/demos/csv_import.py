"""CSV marker tracks to demonstration trials.

The format (one header row, then one row per frame, comma-separated)::

    time,trial,RSHO_x,RSHO_y,RSHO_z,RELB_x,RELB_y,RELB_z,RWRB_x,RWRB_y,RWRB_z
    0.00,0,12.1,-180.3,1402.0,...

A header that lacks a column is shown in the error, which says so if
semicolons or tabs separate its columns (a spreadsheet's other exports).
``time`` is required and increases within a trial, in seconds or, if the
marker map says ``"time_units": "ms"``, milliseconds; a trial whose median
step is outside 0.1 ms to 1 s (1 to 10 000 Hz) is refused, its times not in
that unit (most often milliseconds read as seconds; ``sample_rate``), and
so is one sampled below 20 Hz (frame numbers for times, most often). ``trial`` (a whole
number) is optional and splits the rows into trials (rows of one trial
consecutive, at least two of them); each marker of the marker map
(``markers``) has three columns ``<name>_x``, ``<name>_y``, ``<name>_z`` in
the map's units (default metres). Other columns are ignored. An empty (or
``nan``) marker cell is a missing sample, as capture systems export gaps:
a gap of at most 0.1 s between rows that have the marker is filled, the
number of filled rows reported; a longer one, or one at a trial's first or
last row, is refused (``marker_gaps``). Rows left out are missing samples
too: a time step over 1.6 times the trial's median is frames missing, filled
as empty cells for at most 0.1 s and refused beyond, naming the lines on
both sides (``missing_rows``). A row that
lacks a needed cell (shorter than the header) is refused, as is an empty
time or trial cell.
A file is one subject's: a trial whose upper arm or forearm differs from
the first trial's by more than ``SAME_ARM`` (10 %) is refused, naming the
trials, as two C3D files of one name are (``same_person``).
OptiTrack's own CSV export has several header rows: flatten it to this form.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.importing import MarkerTracks, Report, trial_from_tracks
from shared.demos.markers import TIME_SCALE, MarkerMap
from shared.demos.missing_rows import missing_frames
from shared.demos.same_person import SAME_ARM, same_arm
from shared.demos.sample_rate import check_capture_rate, check_seconds
from shared.demos.trial import MIN_SAMPLES, Trial
from shared.errors import DemoFileError, InvalidInputError

#: What to do with a time column in seconds that the marker map calls ms.
SECONDS_FIX = 'leave "time_units": "ms" out of the marker map'
#: What to do with a time column in milliseconds.
MILLISECONDS_FIX = 'give "time_units": "ms" in the marker map, or divide them by 1000'


class Row(NamedTuple):
    """One data row: its line in the file (from 1) and its cells."""

    line: int
    cells: list[str]


def read_csv(
    path: str | Path, markers: MarkerMap, *, report: Report | None = None
) -> tuple[list[Trial], Subject]:
    """The trials in a CSV file, retargeted to NAO, and the subject's arm.

    Args:
        path: The CSV file.
        markers: Which markers are shoulder, elbow, wrist (and thumb).
        report: Gets a one-line note per trial of the rows where a missing
            marker was filled, if any.

    Raises:
        DemoFileError: if the file is missing or empty, lacks a column (the
            error names it), has a row without a needed cell, a trial that is
            not a whole number, a value that is not a finite number (naming
            line, column and value), a trial of a single row, times that do
            not increase within a trial or are not in seconds (each naming
            the trial and line), an implausible arm
            (``importing.check_segments``), or trials whose arms differ by
            more than ``SAME_ARM`` (two people; naming the trials).
    """
    path = Path(path)
    header, rows = _rows(path)
    columns = _columns(header, markers, str(path))
    groups = _trials(rows, header, str(path))
    name = markers.subject or path.stem
    trials, people = [], []
    for key, group in groups.items():
        tracks = _tracks(group, columns, header, markers, str(path), key)
        trial, person = trial_from_tracks(
            tracks, markers, name, key, str(path), report=report
        )
        trials.append(trial)
        people.append(person)
    _check_one_person(people, groups, str(path))
    subject = Subject(
        name,
        people[0].stature,
        float(np.median([p.upper_arm for p in people])),
        float(np.median([p.forearm for p in people])),
    )
    return trials, subject


def _check_one_person(
    people: list[Subject], groups: dict[int, list[Row]], path: str
) -> None:
    """Refuse trials whose arms are not the first trial's (``same_arm``).

    Args:
        people: Each trial's measured arm [m], in the order of ``groups``.
        groups: Each trial's rows, by trial number.
        path: The file, for messages.

    Raises:
        DemoFileError: naming the subject, the trials that differ and, for
            the first of them and the first trial, their lines and arms.
    """
    numbers = list(groups)
    first = people[0]
    odd = [k for k, p in zip(numbers, people, strict=True) if not same_arm(first, p)]
    if not odd:
        return
    other = people[numbers.index(odd[0])]

    def lines(key: int) -> str:
        return f"lines {groups[key][0].line}-{groups[key][-1].line}"

    raise DemoFileError(
        path,
        f"subject {first.name!r}: the arm of trial{'s' if len(odd) > 1 else ''} "
        f"{', '.join(map(str, odd))} is not trial {numbers[0]}'s: trial {odd[0]} "
        f"({lines(odd[0])}) measures {other.upper_arm:.3f} + {other.forearm:.3f} m, "
        f"trial {numbers[0]} ({lines(numbers[0])}) {first.upper_arm:.3f} + "
        f"{first.forearm:.3f} m, more than {SAME_ARM:.0%} apart: two people in one "
        "file? Give each person a file of their own and a name (the marker "
        'map\'s "subject")',
        subject=first.name,
        trials=odd,
    )


def _rows(path: Path) -> tuple[list[str], list[Row]]:
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
    except (csv.Error, UnicodeDecodeError) as exc:
        raise DemoFileError(str(path), f"not a CSV file ({exc})") from None
    if len(table) < 2:
        raise DemoFileError(str(path), "needs a header row and at least one data row")
    return [h.strip() for h in table[0].cells], table[1:]


def _columns(header: list[str], markers: MarkerMap, path: str) -> dict[str, list[int]]:
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
            f"{', '.join(missing)}{_header_read(header)}",
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


def _header_read(header: list[str]) -> str:
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


def _trials(rows: list[Row], header: list[str], path: str) -> dict[int, list[Row]]:
    """The rows of each trial, in file order (all in trial 0 without ``trial``)."""
    if "trial" not in header:
        return {0: rows}
    index = header.index("trial")
    groups: dict[int, list[Row]] = {}
    last: int | None = None
    for row in rows:
        key = _trial_number(_cell(row, index, header, path), row.line, path)
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


def _cell(row: Row, index: int, header: list[str], path: str) -> str:
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


def _number(text: str, line: int, column: str, path: str) -> float:
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


def _tracks(
    rows: list[Row],
    columns: dict[str, list[int]],
    header: list[str],
    markers: MarkerMap,
    path: str,
    trial: int,
) -> MarkerTracks:
    """The marker tracks of one trial's rows (in the file's units, times [s])."""

    def column(index: int) -> np.ndarray:
        return np.array(
            [
                _number(_cell(row, index, header, path), row.line, header[index], path)
                for row in rows
            ]
        )

    times = TIME_SCALE[markers.time_units] * column(columns["time"][0])
    _check_times(times, rows, path, trial, markers.time_units)
    lines = [row.line for row in rows]
    frames = missing_frames(times, lines, f"trial {trial}", path)
    points = {}
    for role, cols in columns.items():
        if role != "time":
            points[role] = np.full((len(frames.times), 3), np.nan)
            points[role][frames.rows] = np.stack([column(i) for i in cols], axis=1)
    framed: list[int | None] = [None] * len(frames.times)
    for k, line in zip(frames.rows, lines, strict=True):
        framed[k] = line
    return MarkerTracks(frames.times, points, markers.units or "m", framed)


def _check_times(
    times: np.ndarray, rows: list[Row], path: str, trial: int, unit: str
) -> None:
    """Refuse a trial's times [s]: one row, a gap, a step back, or a wrong unit.

    A missing time or one not after the row before names its line; times
    not in the map's ``unit`` (``sample_rate.check_seconds``) or sampled
    too slowly for a capture (``check_capture_rate``) name the trial's lines.
    """
    if len(rows) < MIN_SAMPLES:
        raise DemoFileError(
            path,
            f"trial {trial} has a single row (line {rows[0].line}); a trial needs "
            f"at least {MIN_SAMPLES} samples, from its start to its goal",
            trial=trial,
            line=rows[0].line,
        )
    what = f"the times of trial {trial} must be given and increase"
    missing = np.flatnonzero(~np.isfinite(times))
    if missing.size:
        line = rows[int(missing[0])].line
        raise DemoFileError(path, f"{what}: line {line} has none", line=line)
    back = np.flatnonzero(np.diff(times) <= 0)
    if back.size:
        k = int(back[0]) + 1
        raise DemoFileError(
            path,
            f"{what}: line {rows[k].line} has t = {times[k]:g} s, line "
            f"{rows[k - 1].line} t = {times[k - 1]:g} s",
            line=rows[k].line,
        )
    span = f"trial {trial} (lines {rows[0].line}-{rows[-1].line})"
    if unit != "s":
        span += f", its times read as {unit} as the marker map says"
    try:
        check_seconds([times], span, MILLISECONDS_FIX, SECONDS_FIX)
        check_capture_rate(times, span)
    except InvalidInputError as exc:
        raise DemoFileError(
            path, exc.message, trial=trial, line=rows[0].line, **exc.evidence
        ) from None
