"""The marker map: which recorded markers are the shoulder, elbow and wrist.

A JSON file, read by ``armplan demos import ... --markers MAP.json``::

    {
      "shoulder": "RSHO",      marker on the shoulder joint centre (acromion)
      "elbow": "RELB",         marker on the elbow (lateral epicondyle)
      "wrist": "RWRB",         marker on the wrist (ulnar styloid)
      "thumb": "RWRA",         optional: thumb-side wrist marker (radial
                               styloid); gives the forearm's roll
      "arm": "right",          optional: which arm (default right; left
                               markers without it are refused,
                               ``shared.demos.marker_side``)
      "units": "mm",           optional: m, cm or mm; default the file's own
                               (C3D POINT:UNITS) or m for CSV
      "time_units": "ms",      optional, CSV only: s or ms, the unit of the
                               time column; default s (a C3D file gives its
                               own frame rate)
      "axes": ["x", "y", "z"], optional: the file's axes pointing forward,
                               left and up, a leading "-" flips one; e.g.
                               ["-z", "-x", "y"] for a Y-up capture facing -z;
                               they must turn the capture, not mirror it
      "subject": "P01",        optional: subject name (default the file name,
                               which may have 64 characters at most)
      "stature": 1.72          optional: the subject's height [m]
    }

Each role needs its own marker: a map giving one marker to two roles (say
shoulder and elbow) would make a zero-length arm segment, and is refused.

The axes must form a rotation (determinant +1): motion capture frames are
right-handed, as NAO's torso frame is, and axes that mirror the capture
(``["-z", "x", "y"]``, determinant -1) turn a right arm into a left one; such
a map was accepted, and only ``armplan fit``'s "0.0 % explained" showed it.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, field_validator

from shared.demos.marker_side import other_side_named
from shared.demos.rotations import FloatArray
from shared.errors import DemoFileError, InvalidInputError
from shared.input_files import read_at_most
from shared.messages.base import Message, parse
from shared.robot.side import Side, SideAnyCase

#: Longest subject name (``DemoSubject.name``) [characters].
MAX_SUBJECT = 64
#: Metres per unit.
UNIT_SCALE = {"m": 1.0, "cm": 0.01, "mm": 0.001}
#: Seconds per time unit.
TIME_SCALE = {"s": 1.0, "ms": 0.001}
_AXES = ("x", "y", "z")


class MarkerMap(Message):
    """Marker names and conventions of a recording (see the module docstring)."""

    shoulder: str = Field(min_length=1)
    elbow: str = Field(min_length=1)
    wrist: str = Field(min_length=1)
    thumb: str | None = None
    arm: SideAnyCase = Side.RIGHT
    units: Literal["m", "cm", "mm"] | None = None
    time_units: Literal["s", "ms"] = "s"
    axes: tuple[str, str, str] = ("x", "y", "z")
    subject: str | None = Field(default=None, min_length=1, max_length=MAX_SUBJECT)
    stature: float | None = Field(default=None, gt=0.0, le=3.0)

    @field_validator("axes")
    @classmethod
    def _check_axes(cls, axes: tuple[str, str, str]) -> tuple[str, str, str]:
        names = [a.lstrip("-").lower() for a in axes]
        if sorted(names) != list(_AXES) or any(a.count("-") > 1 for a in axes):
            raise ValueError(
                f"axes must name x, y and z once each, optionally with '-', got {axes}"
            )
        if _determinant(axes) < 0:
            raise ValueError(
                f"axes {list(axes)} mirror the capture (determinant -1): a right "
                "arm would read as a left one; they must turn it (a rotation, "
                "determinant +1): flip the sign of the one axis that is wrong"
            )
        return axes

    @property
    def names(self) -> dict[str, str]:
        """Role (shoulder, elbow, wrist, thumb) to marker name, for given ones."""
        roles = {"shoulder": self.shoulder, "elbow": self.elbow, "wrist": self.wrist}
        if self.thumb is not None:
            roles["thumb"] = self.thumb
        return roles

    def subject_of(self, path: Path) -> str:
        """The subject's name: the map's ``subject``, else the file's stem.

        Raises:
            DemoFileError: if the map has none and the file's name is longer
                than a subject's may be (``MAX_SUBJECT``): a lab's long take
                names (session, participant, condition, take) were read
                whole, and the demonstration file was refused as it was
                written, after every file had been imported.
        """
        if self.subject is not None:
            return self.subject
        if len(path.stem) > MAX_SUBJECT:
            raise DemoFileError(
                str(path),
                f"the subject's name would be the file's, {len(path.stem)} "
                f"characters, over the {MAX_SUBJECT} a subject's name may have: "
                'give "subject" in the marker map (one map per subject)',
                subject=path.stem,
            )
        return path.stem

    def to_torso_axes(self, points: FloatArray) -> FloatArray:
        """Points in the file's axes to forward/left/up axes, shape (..., 3)."""
        out = np.empty_like(points)
        for column, axis in enumerate(self.axes):
            sign = -1.0 if axis.startswith("-") else 1.0
            out[..., column] = sign * points[..., _AXES.index(axis.lstrip("-").lower())]
        return out


def _determinant(axes: tuple[str, str, str]) -> float:
    """Determinant of the signed permutation ``axes`` name (+1 or -1)."""
    matrix = np.zeros((3, 3))
    for row, axis in enumerate(axes):
        sign = -1.0 if axis.startswith("-") else 1.0
        matrix[row, _AXES.index(axis.lstrip("-").lower())] = sign
    return float(np.linalg.det(matrix))


def read_marker_map(path: str | Path) -> MarkerMap:
    """The marker map in a JSON file.

    Raises:
        DemoFileError: if the file is missing, not JSON (or not text), not a marker map
            (naming the field that is wrong), gives one marker to two roles,
            or gives no ``arm`` with markers named like the left arm's.
    """
    path = Path(path)
    try:
        text = read_at_most(path).decode()
    except OSError as exc:
        raise DemoFileError(
            str(path), f"cannot read the marker map: {exc.strerror}"
        ) from None
    except UnicodeDecodeError as exc:  # a C3D or other binary file given as map
        raise DemoFileError(
            str(path),
            f"the marker map is not JSON text (byte {exc.start} is not UTF-8): "
            "give the JSON file that names the markers, not a capture",
        ) from None
    try:
        markers = parse(MarkerMap, json.loads(text))
    except json.JSONDecodeError as exc:
        raise DemoFileError(
            str(path), f"the marker map is not valid JSON ({exc})"
        ) from None
    except InvalidInputError as exc:
        raise DemoFileError(str(path), exc.message) from None
    _check_distinct(markers, str(path))
    _check_arm_given(markers, str(path))
    return markers


def _check_arm_given(markers: MarkerMap, path: str) -> None:
    """Raise DemoFileError if the map gives no arm and its names say the left.

    Without ``arm`` the map means the right arm; markers named like the
    left arm's (``LSHO``, ``LELB``, ``LWRB``) would be imported as a right
    arm's (``shared.demos.marker_side``). A map that gives ``arm`` is taken
    at its word (the import notes the disagreement).
    """
    if "arm" in markers.model_fields_set:
        return
    named = other_side_named(markers.names, markers.arm)
    if named is not None:
        raise DemoFileError(
            path,
            f'{named}, but the map gives no "arm", which means the right arm: '
            'give "arm": "left" if they are the left arm\'s (or "arm": "right" '
            "if they are not)",
            arm=markers.arm.value,
            markers=list(markers.names.values()),
        )


def _check_distinct(markers: MarkerMap, path: str) -> None:
    """Raise DemoFileError if one marker is given for several roles.

    Two roles on one marker make a zero-length segment (no direction to
    retarget), e.g. shoulder and elbow on ``RSHO``.
    """
    roles: dict[str, list[str]] = {}
    for role, name in markers.names.items():
        roles.setdefault(name, []).append(role)
    for name, used in roles.items():
        if len(used) > 1:
            listed = ", ".join(used[:-1]) + " and " + used[-1]
            raise DemoFileError(
                path,
                f"the marker map gives marker {name!r} for {listed}: each needs "
                "its own marker, else the arm has a zero-length segment",
                marker=name,
                roles=used,
            )
