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
Every refusal of a trial names the lines (from 1) of the rows at fault, or
the trial's lines for a fault of the whole trial, in its message and its
evidence (``sample_lines``); each trial keeps its rows' lines (``Trial.lines``)
for the checks of ``armplan demos import``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.csv_table import (
    Row,
    cell,
    columns_of,
    number,
    read_table,
    trial_rows,
)
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
    name = markers.subject_of(path)
    header, rows = read_table(path)
    columns = columns_of(header, markers, str(path))
    groups = trial_rows(rows, header, str(path))
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
                number(cell(row, index, header, path), row.line, header[index], path)
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
        raise DemoFileError(
            path, f"{what}: line {line} has none", trial=trial, line=line
        )
    back = np.flatnonzero(np.diff(times) <= 0)
    if back.size:
        k = int(back[0]) + 1
        raise DemoFileError(
            path,
            f"{what}: line {rows[k].line} has t = {times[k]:g} s, line "
            f"{rows[k - 1].line} t = {times[k - 1]:g} s",
            trial=trial,
            line=rows[k].line,
            previous_line=rows[k - 1].line,
        )
    span = f"trial {trial} (lines {rows[0].line}-{rows[-1].line})"
    if unit != "s":
        span += f", its times read as {unit} as the marker map says"
    try:
        check_seconds([times], span, MILLISECONDS_FIX, SECONDS_FIX)
        check_capture_rate(times, span)
    except InvalidInputError as exc:
        raise DemoFileError(
            path,
            exc.message,
            trial=trial,
            line=rows[0].line,
            last_line=rows[-1].line,
            **exc.evidence,
        ) from None
