"""CSV marker tracks to demonstration trials.

The format (one header row, then one row per frame, comma-separated)::

    time,trial,RSHO_x,RSHO_y,RSHO_z,RELB_x,RELB_y,RELB_z,RWRB_x,RWRB_y,RWRB_z
    0.00,0,12.1,-180.3,1402.0,...

``time`` [s] is required and increases within a trial; ``trial`` (an
integer) is optional and splits the rows into trials (rows of one trial
consecutive); each marker of the marker map (``markers``) has three columns
``<name>_x``, ``<name>_y``, ``<name>_z`` in the map's units (default
metres). Other columns are ignored; empty cells are missing samples.
OptiTrack's own CSV export has several header rows: flatten it to this form.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.importing import MarkerTracks, trial_from_tracks
from shared.demos.markers import UNIT_SCALE, MarkerMap
from shared.demos.trial import Trial
from shared.errors import DemoFileError


def read_csv(path: str | Path, markers: MarkerMap) -> tuple[list[Trial], Subject]:
    """The trials in a CSV file, retargeted to NAO, and the subject's arm.

    Raises:
        DemoFileError: if the file is missing or empty, lacks a column (the
            error names it), holds a value that is not a number, or has times
            that do not increase within a trial.
    """
    path = Path(path)
    header, rows = _rows(path)
    columns = _columns(header, markers, str(path))
    trial_of = header.index("trial") if "trial" in header else None
    groups: dict[int, list[list[str]]] = {}
    order: list[int] = []
    for row in rows:
        key = (
            int(_number(row[trial_of], str(path), "trial"))
            if trial_of is not None
            else 0
        )
        if key not in groups:
            order.append(key)
            groups[key] = []
        elif order[-1] != key:
            raise DemoFileError(
                str(path), f"the rows of trial {key} are not consecutive"
            )
        groups[key].append(row)
    scale = UNIT_SCALE[markers.units or "m"]
    name = markers.subject or path.stem
    trials, people = [], []
    for key in order:
        tracks = _tracks(groups[key], columns, scale, str(path), key)
        trial, person = trial_from_tracks(tracks, markers, name, key, str(path))
        trials.append(trial)
        people.append(person)
    subject = Subject(
        name,
        people[0].stature,
        float(np.median([p.upper_arm for p in people])),
        float(np.median([p.forearm for p in people])),
    )
    return trials, subject


def _rows(path: Path) -> tuple[list[str], list[list[str]]]:
    try:
        with open(path, newline="") as stream:
            table = [row for row in csv.reader(stream) if row]
    except OSError as exc:
        raise DemoFileError(str(path), f"cannot read it: {exc.strerror}") from None
    except (csv.Error, UnicodeDecodeError) as exc:
        raise DemoFileError(str(path), f"not a CSV file ({exc})") from None
    if len(table) < 2:
        raise DemoFileError(str(path), "needs a header row and at least one data row")
    return [h.strip() for h in table[0]], table[1:]


def _columns(header: list[str], markers: MarkerMap, path: str) -> dict[str, list[int]]:
    """Column indices: ``time`` and the x, y, z of each mapped marker."""
    wanted = {"time": ["time"]}
    for role, name in markers.names.items():
        wanted[role] = [f"{name}_{axis}" for axis in "xyz"]
    missing = [c for cols in wanted.values() for c in cols if c not in header]
    if missing:
        raise DemoFileError(
            path,
            f"lacks the column{'s' if len(missing) > 1 else ''} {', '.join(missing)}",
        )
    return {role: [header.index(c) for c in cols] for role, cols in wanted.items()}


def _number(cell: str, path: str, column: str) -> float:
    text = cell.strip()
    if not text:
        return math.nan
    try:
        return float(text)
    except ValueError:
        raise DemoFileError(
            path, f"column {column!r} holds {text!r}, which is not a number"
        ) from None


def _tracks(
    rows: list[list[str]],
    columns: dict[str, list[int]],
    scale: float,
    path: str,
    trial: int,
) -> MarkerTracks:
    def column(index: int, name: str) -> np.ndarray:
        return np.array(
            [
                _number(row[index] if index < len(row) else "", path, name)
                for row in rows
            ]
        )

    times = column(columns["time"][0], "time")
    if not np.all(np.isfinite(times)) or not np.all(np.diff(times) > 0):
        raise DemoFileError(
            path, f"the times of trial {trial} must be given and increase"
        )
    points = {
        role: np.stack([column(i, role) for i in cols], axis=1)
        for role, cols in columns.items()
        if role != "time"
    }
    return MarkerTracks(times, points, scale)
