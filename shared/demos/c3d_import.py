"""C3D motion capture (the field's file format) to a demonstration trial.

One C3D file holds one trial. The markers named by the marker map
(``markers``) are read with ezc3d at the file's point rate; units come from
the map or the file's POINT:UNITS parameter. Labels match exactly, or after
a ``Subject:`` prefix (``Sub1:RSHO`` matches ``RSHO``) if only one does: a
capture of two people (``Sub1:RSHO`` and ``Sub2:RSHO``) needs the full label.
Labels past the 255th continue in POINT:LABELS2, LABELS3, ...; a mapped label
that several points carry is refused.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import Any

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.c3d_layout import C3DLayout, check_c3d_layout
from shared.demos.c3d_reading import read_c3d_file
from shared.demos.importing import MarkerTracks, Report, trial_from_tracks
from shared.demos.markers import UNIT_SCALE, MarkerMap
from shared.demos.sample_rate import MIN_CAPTURE_RATE
from shared.demos.trial import Trial
from shared.errors import DemoFileError
from shared.messages.motion_model import MAX_SAMPLE_RATE, MIN_SAMPLE_RATE


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
        report: Gets one-line notes: the frames where a missing marker was
            filled, a goal NAO cannot reach (``importing.trial_from_tracks``).

    Raises:
        DemoFileError: if the file cannot be read as C3D (a corrupt header
            or parameter section, ``c3d_layout``; ezc3d failing, crashing or
            running out of its memory, ``c3d_reading``), lacks a mapped marker
            (the error names the missing ones and lists those present), has
            unknown units, a point rate outside ``MIN_SAMPLE_RATE`` to
            ``MAX_SAMPLE_RATE``, too few complete frames, or an implausible
            arm (``importing.check_segments``).
    """
    path = Path(path)
    name = markers.subject_of(path)
    layout = check_c3d_layout(path)
    data = read_c3d_file(path)
    point = data["parameters"]["POINT"]
    cloud = data["data"]["points"]  # (3, markers, frames)
    labels = point_labels(point, cloud.shape[1])
    index = _marker_indices(labels, markers, str(path))
    rate = _rate(path, data)
    _check_whole(path, layout, cloud.shape[2])
    _check_not_cut(path, data, cloud.shape[2], rate)
    times = np.arange(cloud.shape[2]) / rate
    points = {role: cloud[:, i, :].T for role, i in index.items()}
    units = markers.units or _units(point, str(path))
    return trial_from_tracks(
        MarkerTracks(times, points, units),
        markers,
        name,
        trial,
        str(path),
        report=report,
    )


def _rate(path: Path, data: Any) -> float:
    """The file's point rate [Hz], refused outside the demonstrations' range.

    The frames' times are counted at this rate, so a rate no capture of a
    reach uses (a corrupt header, or a field meant for another unit) would
    stretch or squeeze the whole trial; ``armplan fit`` would refuse it
    later, the import names the file now. Nor below ``MIN_CAPTURE_RATE``,
    as a CSV trial: a 100 Hz reach whose header said 10 Hz was imported as
    a 6.7 s reach without a word.
    """
    rate = float(data["header"]["points"]["frame_rate"])
    if not (math.isfinite(rate) and MIN_SAMPLE_RATE <= rate <= MAX_SAMPLE_RATE):
        raise DemoFileError(
            str(path),
            f"its point rate is {rate:g} Hz; demonstrations are sampled at "
            f"{MIN_SAMPLE_RATE:g} to {MAX_SAMPLE_RATE:g} Hz",
            rate=rate,
        )
    if rate < MIN_CAPTURE_RATE:
        raise DemoFileError(
            str(path),
            f"its point rate is {rate:g} Hz; motion capture samples at "
            f"{MIN_CAPTURE_RATE:g} Hz or more: is the header's rate right? (a "
            "CSV sampled below it is refused too)",
            rate=rate,
        )
    return rate


#: The header's last frame when the file holds more than a 16-bit count.
MANY_FRAMES = 65535


def _check_whole(path: Path, layout: C3DLayout, frames: int) -> None:
    """Raise if the file holds fewer frames than its header says.

    ezc3d reads a cut file without complaint, and shortens its header and
    parameters to what it read: a file cut in half became a trial of a
    third of its frames, whose last frame (the reach's goal) was mid-reach.
    So the header's own first and last frame are compared with those read.

    Raises:
        DemoFileError: naming both counts.
    """
    said = layout.last - layout.first + 1
    if layout.last == MANY_FRAMES or said <= frames:
        return
    raise DemoFileError(
        str(path),
        f"truncated: its header says {said} frames ({layout.first}..{layout.last}), "
        f"only {frames} could be read",
    )


def _check_not_cut(path: Path, data: Any, frames: int, rate: float) -> None:
    """Raise if the file holds more frames than the ``frames`` ezc3d read.

    A C3D header counts frames in 16 bits; a longer capture says 65,535 there
    and its true count in TRIAL:ACTUAL_END_FIELD or POINT:LONG_FRAMES (or
    nowhere: ezc3d writes neither). ezc3d 1.7 reads the header's count, so a
    70 s capture at 1 kHz became its first 65.5 s, and the reach at its end
    was lost without a word. The frames on disk are counted from the file's
    size, the data's start and a frame's size.

    Args:
        path: The C3D file.
        data: What ezc3d read of it.
        frames: The frames ezc3d read.
        rate: The point rate [Hz].

    Raises:
        DemoFileError: naming the frames held and read, and what to do.
    """
    if frames < MANY_FRAMES:
        return
    said = _long_count(data["parameters"])
    held = said or _frames_on_disk(path, data, rate)
    if held is None or held <= frames:
        return
    raise DemoFileError(
        str(path),
        f"holds {'' if said else 'at least '}{held} frames ({held / rate:.1f} s "
        f"at {rate:g} Hz), more than "
        f"the {MANY_FRAMES} a C3D header counts: only the first {frames} "
        f"({frames / rate:.1f} s) can be read, cutting the trial short of its "
        "end. A trial is one reach, a second or two: crop the capture to the "
        "reach and export it again",
        frames=held,
        read=frames,
    )


def _long_count(parameters: Any) -> int | None:
    """The frame count a long capture's parameters give, or ``None``.

    TRIAL:ACTUAL_END_FIELD (two 16-bit words, low first) is the last frame
    (from 1), TRIAL:ACTUAL_START_FIELD the first; POINT:LONG_FRAMES the count.
    """
    trial = parameters.get("TRIAL", {})
    if "ACTUAL_END_FIELD" in trial:
        end = [int(v) & 0xFFFF for v in trial["ACTUAL_END_FIELD"]["value"]]
        start = [
            int(v) & 0xFFFF
            for v in trial.get("ACTUAL_START_FIELD", {}).get("value", [1, 0])
        ]
        if len(end) == 2 and len(start) == 2:
            return (end[0] + (end[1] << 16)) - (start[0] + (start[1] << 16)) + 1
    values = parameters["POINT"].get("LONG_FRAMES", {}).get("value", [])
    return int(values[0]) if len(values) else None


def _frames_on_disk(path: Path, data: Any, rate: float) -> int | None:
    """Whole frames between the data's start and the file's end, or ``None``.

    A frame is 4 values per point and the analog samples of its period, each
    a 4-byte float (POINT:SCALE < 0) or a 2-byte integer. The last block's
    padding (under 512 bytes) is not counted as frames.
    """
    point = data["parameters"]["POINT"]
    analogs = data["header"]["analogs"]
    per_frame = 4 * int(data["header"]["points"]["size"])
    if int(analogs["size"]) and rate > 0:
        per_frame += int(analogs["size"]) * round(float(analogs["frame_rate"]) / rate)
    width = 4 if float(point["SCALE"]["value"][0]) < 0 else 2
    start = (int(point["DATA_START"]["value"][0]) - 1) * 512
    body = path.stat().st_size - start
    if per_frame == 0 or body < 0:
        return None
    return max(0, body - (BLOCK - 1)) // (per_frame * width) or None


#: A C3D file's block [bytes]: the data's last block is padded to it.
BLOCK = 512


def point_labels(point: dict[str, Any], count: int) -> list[str]:
    """The labels of a C3D file's ``count`` points, in their order.

    A C3D parameter holds at most 255 labels: a capture of more points
    continues them in POINT:LABELS2, LABELS3 and so on. Labels past
    ``count`` (POINT:USED) name no point and are left out.

    Args:
        point: The file's POINT parameters, as ezc3d reads them.
        count: Its points.
    """
    labels: list[str] = []
    for number in itertools.count(1):
        key = "LABELS" if number == 1 else f"LABELS{number}"
        if key not in point or len(labels) >= count:
            break
        labels.extend(str(label).strip() for label in point[key]["value"])
    return labels[:count]


def _marker_indices(labels: list[str], markers: MarkerMap, path: str) -> dict[str, int]:
    """Index of each mapped marker among the file's labels.

    Raises:
        DemoFileError: if a mapped name matches no label; is the label of
            several points (which one is the marker is unknown); or, after a
            ``Subject:`` prefix, matches several labels (two people in one
            capture): naming the matches and the full label to map instead.
    """
    bare = [label.split(":")[-1] for label in labels]
    found, missing = {}, []
    for role, name in markers.names.items():
        exact = [i for i, label in enumerate(labels) if label == name]
        after = [i for i, label in enumerate(bare) if label == name]
        matches = exact or after
        distinct = list(dict.fromkeys(labels[i] for i in matches))
        if len(distinct) > 1:
            _ambiguous(role, name, distinct, path)
        elif len(matches) > 1:
            _repeated(role, labels[matches[0]], matches, path)
        elif matches:
            found[role] = matches[0]
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


def _ambiguous(role: str, name: str, matches: list[str], path: str) -> None:
    """Raise: the mapped ``name`` is the label of several people's markers."""
    raise DemoFileError(
        path,
        f"the mapped marker {role} {name!r} is ambiguous: the C3D file has "
        f"{', '.join(matches)} (one per subject); map the one to import by its "
        f'full label, e.g. "{role}": "{matches[0]}"',
        role=role,
        matches=matches,
    )


def _repeated(role: str, label: str, indices: list[int], path: str) -> None:
    """Raise: the mapped marker's ``label`` names several points of the file."""
    points = ", ".join(str(i + 1) for i in indices)
    raise DemoFileError(
        path,
        f"the mapped marker {role} {label!r} is the label of {len(indices)} points "
        f"of the C3D file (points {points}), so which one is the {role} is "
        "unknown; give the others other labels in the capture software and "
        "export again",
        role=role,
        label=label,
        points=[i + 1 for i in indices],
    )


def _units(point: dict[str, Any], path: str) -> str:
    values = point.get("UNITS", {}).get("value", [])
    unit = str(values[0]).strip().lower() if len(values) else "mm"
    if unit not in UNIT_SCALE:
        raise DemoFileError(
            path, f'unknown point units {unit!r}; give "units" in the marker map'
        )
    return unit
