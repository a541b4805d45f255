"""C3D motion capture (the field's file format) to a demonstration trial.

One C3D file holds one trial. The markers named by the marker map
(``markers``) are read with ezc3d at the file's point rate; units come from
the map or the file's POINT:UNITS parameter. Labels match exactly, or after
a ``Subject:`` prefix (``Sub1:RSHO`` matches ``RSHO``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import ezc3d
import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.importing import MarkerTracks, Report, trial_from_tracks
from shared.demos.markers import UNIT_SCALE, MarkerMap
from shared.demos.trial import Trial
from shared.errors import DemoFileError


def read_c3d(
    path: str | Path,
    markers: MarkerMap,
    trial: int = 0,
    *,
    report: Report | None = None,
) -> tuple[Trial, Subject]:
    """The trial recorded in a C3D file, retargeted to NAO.

    Args:
        path: The C3D file.
        markers: Which markers are shoulder, elbow, wrist (and thumb).
        trial: Trial number to give it.
        report: Gets a one-line note of the frames dropped for a missing
            marker, if any.

    Raises:
        DemoFileError: if the file cannot be read as C3D, lacks a mapped marker
            (the error names the missing ones and lists those present), has
            unknown units, too few complete frames, or an implausible arm
            (``importing.check_segments``).
    """
    path = Path(path)
    try:
        data = ezc3d.c3d(str(path))
    except (OSError, RuntimeError, ValueError) as exc:
        raise DemoFileError(str(path), f"not a readable C3D file ({exc})") from None
    point = data["parameters"]["POINT"]
    labels = [str(label).strip() for label in point["LABELS"]["value"]]
    index = _marker_indices(labels, markers, str(path))
    rate = float(data["header"]["points"]["frame_rate"])
    cloud = np.asarray(data["data"]["points"], dtype=float)  # (4, markers, frames)
    times = np.arange(cloud.shape[2]) / rate
    points = {role: cloud[:3, i, :].T for role, i in index.items()}
    units = markers.units or _units(point, str(path))
    name = markers.subject or path.stem
    return trial_from_tracks(
        MarkerTracks(times, points, units),
        markers,
        name,
        trial,
        str(path),
        report=report,
    )


def _marker_indices(labels: list[str], markers: MarkerMap, path: str) -> dict[str, int]:
    """Index of each mapped marker among the file's labels."""
    bare = [label.split(":")[-1] for label in labels]
    found, missing = {}, []
    for role, name in markers.names.items():
        if name in labels:
            found[role] = labels.index(name)
        elif bare.count(name) == 1:
            found[role] = bare.index(name)
        else:
            missing.append(f"{role} {name!r}")
    if missing:
        raise DemoFileError(
            path,
            f"the C3D file lacks the mapped marker{'s' if len(missing) > 1 else ''} "
            f"{', '.join(missing)}; it has {', '.join(labels) or 'no markers'}",
            missing=missing,
            labels=labels,
        )
    return found


def _units(point: dict[str, Any], path: str) -> str:
    values = point.get("UNITS", {}).get("value", [])
    unit = str(values[0]).strip().lower() if len(values) else "mm"
    if unit not in UNIT_SCALE:
        raise DemoFileError(
            path, f'unknown point units {unit!r}; give "units" in the marker map'
        )
    return unit
