"""Recorded marker tracks to a retargeted demonstration trial.

Shared by the C3D and CSV readers: scale to metres, turn the axes to
forward/left/up, refuse a marker more than ``FARTHEST`` from the origin
(not a position), fill a marker's short gaps and refuse the others
(``marker_gaps``; the count of filled frames goes to ``report``), measure
the subject's segment lengths and refuse implausible ones
(``check_segments``), retarget to NAO (``retarget``; a goal NAO cannot
reach gets a note, ``goal_reach``) and, with a thumb marker, build the
wrist frame from the forearm and the thumb side (``thumb_marker`` checks
that marker).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.goal_reach import goal_reach_problem
from shared.demos.marker_gaps import LONGEST_GAP, fill_gaps
from shared.demos.markers import UNIT_SCALE, MarkerMap
from shared.demos.posture_sense import posture_notes
from shared.demos.retarget import ArmTrack, nao_arm_size, retarget
from shared.demos.rotations import FloatArray, unit
from shared.demos.sample_lines import line_evidence, sample_line, trial_span
from shared.demos.thumb_marker import check_thumb, check_turns
from shared.demos.trial import MIN_SAMPLES, Trial
from shared.errors import DemoFileError

#: Farthest a marker may be from the capture's origin [m]: any capture
#: volume is far smaller; beyond it a value is garbage, not a position.
FARTHEST = 1000.0
#: Shortest and longest plausible human upper arm or forearm [m]. Adults'
#: are 0.2..0.4 m (``anthropometry``); the range is generous, so only wrong
#: units or misplaced markers fall outside it.
SEGMENT_RANGE = (0.05, 1.0)
#: Largest relative difference of one frame's segment length from the
#: trial's median: skin markers move a few centimetres, not half an arm.
SEGMENT_SPREAD = 0.5
#: A segment shorter than this [m] has no direction: its markers coincide.
COINCIDENT = 1e-6
#: The arm's segments: name, and the roles of the markers at its ends.
SEGMENTS = (("upper arm", "shoulder", "elbow"), ("forearm", "elbow", "wrist"))

#: Where notes for the user go (e.g. filled frames), one line each.
Report = Callable[[str], None]


class MarkerTracks(NamedTuple):
    """Raw marker trajectories of one trial, in the file's units and axes.

    Attributes:
        times: Frame times [s], shape (n,).
        points: Marker positions by role (shoulder, elbow, wrist, thumb),
            each shape (n, 3).
        units: The file's length unit, a key of ``UNIT_SCALE`` (m, cm, mm).
        lines: The file's line of each frame (CSV; ``None`` for a frame
            of a missing row, ``missing_rows``), or ``None``.
    """

    times: FloatArray
    points: dict[str, FloatArray]
    units: str
    lines: list[int | None] | None = None

    @property
    def scale(self) -> float:
        """Metres per file unit."""
        return UNIT_SCALE[self.units]

    def span(self) -> str:
        """The trial's lines for a message, `` (lines 2-31)``; ``""`` without."""
        return trial_span(self.lines)

    def frame(self, k: int) -> str:
        """Frame ``k`` named for a message: ``frame 4 (t = 0.04 s, line 7)``.

        A frame of a missing row names the rows around it:
        ``frame 5 (t = 0.05 s, no row: between lines 7 and 8)``.
        """
        return f"frame {k} (t = {self.times[k]:g} s{sample_line(self.lines, k)})"

    def evidence(self, first: int, last: int | None = None) -> dict[str, Any]:
        """The lines of frames ``first``..``last`` as evidence (``line_evidence``)."""
        return line_evidence(self.lines, first, last)


def trial_from_tracks(
    tracks: MarkerTracks,
    markers: MarkerMap,
    subject: str,
    trial: int,
    path: str,
    *,
    report: Report | None = None,
) -> tuple[Trial, Subject]:
    """The retargeted trial and the subject's measured arm.

    Args:
        tracks: The trial's raw marker tracks.
        markers: The marker map (roles, arm, axes, declared units).
        subject: The subject's name.
        trial: The trial's number.
        path: The file, for messages.
        report: Gets one-line notes: frames where a missing marker was
            filled (their number), a goal NAO cannot reach
            (``goal_reach_problem``); ``None`` for no notes.

    Raises:
        DemoFileError: if fewer than ``MIN_SAMPLES`` frames have every marker
            (naming subject, trial and, for CSV, its lines), a marker lies
            more than ``FARTHEST`` from the origin, a marker is missing at
            the trial's first or last frame or for longer than
            ``LONGEST_GAP`` (``fill_gaps``, naming marker and frames), a
            segment is degenerate or implausibly long or short
            (``check_segments``), or the thumb-side marker leaves the roll
            undefined or turns it faster than a forearm can (``check_thumb``,
            ``check_turns``, naming the frame).
    """
    points = {
        role: markers.to_torso_axes(p * tracks.scale)
        for role, p in tracks.points.items()
    }
    named = f"subject {subject!r}, trial {trial}"
    where = f"{named}{tracks.span()}"
    _check_near(points, markers, tracks, where, path)
    whole = np.all([np.isfinite(p).all(axis=1) for p in points.values()], axis=0)
    _check_enough(whole, tracks, markers, named, path, trial=trial)
    names = {role: markers.names[role] for role in points}
    points, filled = fill_gaps(
        points, tracks.times, names, tracks.frame, where, path, lines=tracks.lines
    )
    _report_gaps(whole, filled, tracks, trial, path, report)
    check_segments(points, np.arange(len(whole)), tracks, markers, named, path)
    times = tracks.times - tracks.times[0]
    human = ArmTrack(points["shoulder"], points["elbow"], points["wrist"])
    person = Subject(
        subject,
        markers.stature or 0.0,
        float(np.median(np.linalg.norm(human.elbow - human.shoulder, axis=1))),
        float(np.median(np.linalg.norm(human.wrist - human.elbow, axis=1))),
    )
    nao = retarget(human, nao_arm_size(markers.arm))
    unreachable = goal_reach_problem(human, nao, markers.arm)
    if unreachable is not None and report is not None:
        report(f"{path}: {where}: {unreachable}")
    if report is not None:
        for note in posture_notes(human):
            report(f"{path}: {where}: {note}")
    frames = None
    if "thumb" in points:
        thumb = points["thumb"]
        check_thumb(
            human.elbow,
            human.wrist,
            thumb,
            tracks.frame,
            names,
            where,
            path,
            lines=tracks.lines,
        )
        frames = wrist_frames(human.elbow, human.wrist, thumb)
        check_turns(
            frames, tracks.times, tracks.frame, names, where, path, lines=tracks.lines
        )
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
        lines=tracks.lines,
    )
    return made, person


def wrist_frames(elbow: FloatArray, wrist: FloatArray, thumb: FloatArray) -> FloatArray:
    """Wrist frames from the forearm and the thumb side, shape (n, 3, 3).

    x runs along the forearm (elbow to wrist); y = t x x with t the direction
    from the wrist marker to the thumb-side marker, normal to the forearm: the
    palm normal of a right hand (in the anatomical position, palms forward,
    thumbs out, y points forward for both hands; a left hand's palm faces -y,
    as on NAO). ``thumb_marker`` refuses a thumb marker that leaves t
    undefined and frames that turn faster than a forearm (swapped markers).
    """
    x = unit(wrist - elbow)
    side = thumb - wrist
    side = side - np.einsum("ij,ij->i", side, x)[:, None] * x
    y = unit(np.cross(unit(side), x))
    return np.stack((x, y, np.cross(x, y)), axis=-1)


def check_segments(
    points: dict[str, FloatArray],
    kept: np.ndarray,
    tracks: MarkerTracks,
    markers: MarkerMap,
    trial: str,
    path: str,
) -> None:
    """Refuse a degenerate or implausible upper arm or forearm.

    For each segment, over the frames ``kept`` (those with every marker):
    a frame whose two markers coincide (closer than ``COINCIDENT``) is a
    degenerate arm; a median length outside ``SEGMENT_RANGE`` points at
    wrong units; a frame outside that range, or more than ``SEGMENT_SPREAD``
    off the median, at a misplaced or mislabelled marker there.

    Args:
        points: Marker positions [m] by role, torso axes, each shape (n, 3).
        kept: Indices of the frames to check, shape (m,).
        tracks: The raw tracks (frame times, lines, units), for messages.
        markers: The marker map (names and declared units).
        trial: The trial named for messages, e.g. ``"subject 'P01', trial 0"``.
        path: The file, for messages.

    Raises:
        DemoFileError: naming the subject, trial, segment, the length found
            and the frame, or for a median the units read and whether the
            marker map declared them.
    """
    for segment, start, end in SEGMENTS:
        lengths = np.linalg.norm(points[end][kept] - points[start][kept], axis=1)
        ends = f"{markers.names[start]!r} to {markers.names[end]!r}"
        found = _segment_problem(lengths, kept, tracks, markers, f"{segment} ({ends})")
        if found is not None:
            problem, frames = found
            raise DemoFileError(
                path,
                f"{trial}{problem}",
                segment=segment,
                trial=trial,
                **tracks.evidence(*frames),
            )


def _segment_problem(
    lengths: FloatArray,
    kept: np.ndarray,
    tracks: MarkerTracks,
    markers: MarkerMap,
    segment: str,
) -> tuple[str, tuple[int, int]] | None:
    """What is wrong with one segment's lengths [m], shape (m,), or ``None``.

    With the problem, the first and last frame it is at: one frame, or for
    a median the trial's first and last (a CSV message names their lines).
    """
    low, high = SEGMENT_RANGE
    span = f"a human's is {100 * low:g} cm to {high:g} m"
    zero = np.flatnonzero(lengths < COINCIDENT)
    if zero.size:
        k = int(kept[zero[0]])
        return (
            f", {tracks.frame(k)}: degenerate arm, zero-length {segment}: the "
            "markers coincide",
            (k, k),
        )
    median = float(np.median(lengths))
    if not low <= median <= high:
        return (
            f"{tracks.span()}: the {segment} is {_length(median)} long (median of "
            f"{len(lengths)} frames), but {span}; coordinates were read in "
            f"{_units_read(tracks, markers)}: are the units right?",
            (0, len(tracks.times) - 1),
        )
    off = np.abs(lengths / median - 1.0) > SEGMENT_SPREAD
    odd = np.flatnonzero(off | (lengths < low) | (lengths > high))
    if not odd.size:
        return None
    k = int(kept[odd[0]])
    return (
        f", {tracks.frame(k)}: the {segment} is {_length(lengths[odd[0]])} "
        f"long, its median {_length(median)} ({span}): a marker is misplaced "
        "or mislabelled there (empty cells would have it filled from the frames "
        "around, for a gap of a few frames)",
        (k, k),
    )


def _length(metres: float) -> str:
    """A length for a message: ``0.3 mm`` below a centimetre, else ``0.312 m``."""
    return f"{metres * 1000:.3g} mm" if metres < 0.01 else f"{metres:.3g} m"


def _units_read(tracks: MarkerTracks, markers: MarkerMap) -> str:
    """The units the coordinates were read in, and where they came from."""
    if markers.units is not None:
        return f'{tracks.units}, as the marker map\'s "units" declares'
    return f'{tracks.units}, the file\'s default (the marker map has no "units")'


def _check_enough(
    whole: np.ndarray,
    tracks: MarkerTracks,
    markers: MarkerMap,
    named: str,
    path: str,
    *,
    trial: int,
) -> None:
    """Refuse a trial with fewer than ``MIN_SAMPLES`` frames with every marker.

    Args:
        whole: Whether each frame has every marker, shape (n,).
        tracks: The raw tracks (for the trial's lines).
        markers: The marker map (for the markers' names).
        named: The trial named for messages, e.g. ``"subject 'P01', trial 0"``.
        path: The file, for messages.
        trial: The trial's number, for the evidence.
    """
    count = int(whole.sum())
    if count >= MIN_SAMPLES:
        return
    if len(whole) < MIN_SAMPLES:
        found = f"has {len(whole)} frame{'' if len(whole) == 1 else 's'}"
    else:
        found = (
            f"{count} of its {len(whole)} frames {'has' if count == 1 else 'have'} "
            f"all of the markers {', '.join(markers.names.values())} (a frame "
            "with a missing marker is filled only between frames that have it)"
        )
    raise DemoFileError(
        path,
        f"{named}{tracks.span()}: {found}; a trial needs at least {MIN_SAMPLES}"
        + _never_seen(tracks, markers),
        trial=trial,
        frames=len(whole),
        whole=count,
        **tracks.evidence(0, len(whole) - 1),
    )


def _never_seen(tracks: MarkerTracks, markers: MarkerMap) -> str:
    """The mapped markers missing in every frame, for ``_check_enough``.

    A thumb marker lost for a whole take was told only as "0 of its 88
    frames have all of the markers RSHO, RELB, RWRB, RWRA", leaving which
    one to guess; the thumb marker is optional.
    """
    absent = [
        role
        for role in markers.names
        if np.isnan(tracks.points[role]).any(axis=1).all()
    ]
    if not absent:
        return ""
    named = ", ".join(f"{role} {markers.names[role]!r}" for role in absent)
    said = f": {named} {'is' if len(absent) == 1 else 'are'} in no frame"
    if "thumb" in absent:
        said += (
            " (the thumb marker is optional: a map without it imports the "
            "arm without the forearm's roll)"
        )
    return said


def _report_gaps(
    whole: np.ndarray,
    filled: int,
    tracks: MarkerTracks,
    trial: int,
    path: str,
    report: Report | None,
) -> None:
    """Tell ``report`` how many frames had a missing marker filled."""
    gaps = np.flatnonzero(~whole)
    if report is None or not gaps.size:
        return
    report(
        f"{path}: trial {trial}: filled {filled} of {len(whole)} frames where a "
        f"marker was missing (gaps of at most {LONGEST_GAP:g} s, by a smoothing "
        f"spline), the first at {tracks.frame(int(gaps[0]))}"
    )


def _check_near(
    points: dict[str, FloatArray],
    markers: MarkerMap,
    tracks: MarkerTracks,
    where: str,
    path: str,
) -> None:
    """Refuse a marker beyond ``FARTHEST`` from the origin (not a position).

    The error names the trial, the first such marker and frame and, for
    CSV, its line (also in the evidence).

    Non-finite values are missing samples (filled or refused by
    ``fill_gaps``), not positions too far away.
    """
    for role, p in points.items():
        far = np.flatnonzero(np.any(np.isfinite(p) & (np.abs(p) > FARTHEST), axis=1))
        if far.size:
            k = int(far[0])
            line = "" if tracks.lines is None else f" (line {tracks.lines[k]})"
            if 2 * far.size > len(p):
                line += (
                    f"; so are most of its frames: coordinates were read in "
                    f"{_units_read(tracks, markers)}: are the units right?"
                )
            raise DemoFileError(
                path,
                f"{where}: marker {markers.names[role]!r} at frame {k} is at "
                f"{np.array2string(p[k], precision=4)} m, more than "
                f"{FARTHEST:g} m from the origin: not a position{line}",
                marker=markers.names[role],
                frame=k,
                **tracks.evidence(k),
            )
