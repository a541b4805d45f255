"""Recorded marker tracks to a retargeted demonstration trial.

Shared by the C3D and CSV readers: scale to metres, turn the axes to
forward/left/up, drop frames where a marker is missing (refuse one more
than ``FARTHEST`` from the origin: not a position), measure the
subject's segment lengths, retarget to NAO (``retarget``) and, with a thumb
marker, build the wrist frame from the forearm and the thumb side.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.markers import MarkerMap
from shared.demos.retarget import ArmTrack, nao_arm_size, retarget
from shared.demos.rotations import FloatArray, unit
from shared.demos.trial import Trial
from shared.errors import DemoFileError

#: Farthest a marker may be from the capture's origin [m]: any capture
#: volume is far smaller; beyond it a value is garbage, not a position.
FARTHEST = 1000.0


class MarkerTracks(NamedTuple):
    """Raw marker trajectories of one trial, in the file's units and axes.

    Attributes:
        times: Frame times [s], shape (n,).
        points: Marker positions by role (shoulder, elbow, wrist, thumb),
            each shape (n, 3).
        scale: Metres per file unit.
    """

    times: FloatArray
    points: dict[str, FloatArray]
    scale: float


def trial_from_tracks(
    tracks: MarkerTracks, markers: MarkerMap, subject: str, trial: int, path: str
) -> tuple[Trial, Subject]:
    """The retargeted trial and the subject's measured arm.

    Raises:
        DemoFileError: if fewer than two frames have every marker, or a
            marker lies more than ``FARTHEST`` from the origin.
    """
    points = {
        role: markers.to_torso_axes(p * tracks.scale)
        for role, p in tracks.points.items()
    }
    _check_near(points, markers, path)
    whole = np.all([np.isfinite(p).all(axis=1) for p in points.values()], axis=0)
    if int(whole.sum()) < 2:
        raise DemoFileError(
            path,
            f"fewer than two frames have all of the markers "
            f"{', '.join(markers.names.values())}",
        )
    times = tracks.times[whole] - tracks.times[whole][0]
    points = {role: p[whole] for role, p in points.items()}
    human = ArmTrack(points["shoulder"], points["elbow"], points["wrist"])
    person = Subject(
        subject,
        markers.stature or 0.0,
        float(np.median(np.linalg.norm(human.elbow - human.shoulder, axis=1))),
        float(np.median(np.linalg.norm(human.wrist - human.elbow, axis=1))),
    )
    nao = retarget(human, nao_arm_size(markers.arm))
    frames = None
    if "thumb" in points:
        frames = wrist_frames(human.elbow, human.wrist, points["thumb"])
    made = Trial(
        subject=subject,
        trial=trial,
        point=0,
        arm=markers.arm,
        times=times,
        shoulder=nao.shoulder,
        elbow=nao.elbow,
        wrist=nao.wrist,
        wrist_frame=frames,
        target=nao.wrist[-1].copy(),
        labels=None,
    )
    return made, person


def wrist_frames(elbow: FloatArray, wrist: FloatArray, thumb: FloatArray) -> FloatArray:
    """Wrist frames from the forearm and the thumb side, shape (n, 3, 3).

    x runs along the forearm (elbow to wrist); y = t x x with t the direction
    from the wrist marker to the thumb-side marker, normal to the forearm: the
    palm normal of a right hand (in the anatomical position, palms forward,
    thumbs out, y points forward for both hands; a left hand's palm faces -y,
    as on NAO).
    """
    x = unit(wrist - elbow)
    side = thumb - wrist
    side = side - np.einsum("ij,ij->i", side, x)[:, None] * x
    y = unit(np.cross(unit(side), x))
    return np.stack((x, y, np.cross(x, y)), axis=-1)


def _check_near(points: dict[str, FloatArray], markers: MarkerMap, path: str) -> None:
    """Raise DemoFileError naming the first marker and frame beyond ``FARTHEST``.

    Non-finite values are missing samples (their frames are dropped), not
    positions too far away.
    """
    for role, p in points.items():
        far = np.flatnonzero(np.any(np.isfinite(p) & (np.abs(p) > FARTHEST), axis=1))
        if far.size:
            k = int(far[0])
            raise DemoFileError(
                path,
                f"marker {markers.names[role]!r} at frame {k} is at "
                f"{np.array2string(p[k], precision=4)} m, more than "
                f"{FARTHEST:g} m from the origin: not a position",
            )
