"""The thumb-side wrist marker gives the forearm's roll: refuse one that cannot.

``importing.wrist_frames`` takes the palm normal from the direction, normal
to the forearm, from the wrist marker to the thumb-side marker (on an
adult's wrist the radial and ulnar styloids, about 5 cm apart). A thumb
marker on top of the wrist marker, or on the forearm's axis, leaves that
direction undefined (the frame came out arbitrary, silently); the two
markers swapped for 6 frames turned the palm normal by 180 deg there and
back, silently. ``check_thumb`` refuses the first, as ``check_segments``
does a degenerate arm; ``check_turns`` the second: a wrist frame turning
between two frames faster than a forearm can.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from shared.demos.rotations import FloatArray, unit
from shared.demos.sample_lines import Lines, line_evidence
from shared.errors import DemoFileError

#: Nearest and farthest the thumb-side marker may be from the forearm's axis
#: through the wrist marker [m]. An adult's wrist is about 5 cm across; below
#: 1 cm (a marker ball is 9-14 mm wide) 1 mm of marker jitter turns the palm
#: by over 6 degrees, and at 0 its direction is undefined. Beyond 15 cm the
#: marker is not on the wrist.
THUMB_OFFSET = (0.01, 0.15)
#: Largest relative difference of one frame's offset from the trial's median:
#: skin markers move millimetres, not half a wrist.
THUMB_SPREAD = 0.5
#: Fastest the wrist frame may turn [rad/s], about 2,900 deg/s: a forearm
#: turns at thousands of degrees per second only in throwing, a reach far
#: slower.
FASTEST_TURN = 50.0
#: Least turn between two frames refused [rad] (20 deg): at high sample rates
#: marker jitter alone turns the frame a few degrees per frame.
LEAST_REFUSED_TURN = np.radians(20.0)
#: Most turn between two frames accepted at any rate [rad] (90 deg): beyond a
#: quarter turn a turn cannot be told from swapped markers.
MOST_TURN = np.pi / 2

#: Frame ``k`` named for a message: ``frame 4 (t = 0.04 s, line 7)``.
FrameName = Callable[[int], str]


def check_thumb(
    elbow: FloatArray,
    wrist: FloatArray,
    thumb: FloatArray,
    frame: FrameName,
    names: dict[str, str],
    where: str,
    path: str,
    *,
    lines: Lines = None,
) -> None:
    """Refuse a thumb-side marker too near or far from the forearm's axis.

    Args:
        elbow: Elbow marker positions [m], shape (n, 3).
        wrist: Wrist marker positions [m], shape (n, 3).
        thumb: Thumb-side marker positions [m], shape (n, 3).
        frame: Names frame ``k`` for messages.
        names: The markers' names by role (``wrist``, ``thumb``).
        where: The trial named for messages, e.g. ``"subject 'P01', trial 0"``.
        path: The file, for messages.
        lines: Each frame's line in a CSV file (``sample_lines``), for the
            evidence, or ``None``.

    Raises:
        DemoFileError: naming the trial, the frame and the offset found.
    """
    offsets = np.linalg.norm(_across(elbow, wrist, thumb), axis=1)
    found = _offset_problem(offsets, frame, names)
    if found is not None:
        problem, k = found
        raise DemoFileError(
            path,
            f"{where}{problem}",
            marker=names["thumb"],
            frame=k,
            **line_evidence(lines, k),
        )


def _across(elbow: FloatArray, wrist: FloatArray, thumb: FloatArray) -> FloatArray:
    """The wrist-to-thumb vectors normal to the forearm [m], shape (n, 3)."""
    x = unit(wrist - elbow)
    side = thumb - wrist
    return np.asarray(side - np.einsum("ij,ij->i", side, x)[:, None] * x)


def _offset_problem(
    offsets: FloatArray, frame: FrameName, names: dict[str, str]
) -> tuple[str, int] | None:
    """What is wrong with the thumb's offsets [m], shape (n,), or ``None``.

    With the problem, the frame it is at.
    """
    low, high = THUMB_OFFSET
    marker = f"the thumb-side marker {names['thumb']!r}"
    axis = f"the forearm's axis through the wrist marker {names['wrist']!r}"
    span = f"{1000 * low:g} to {1000 * high:g} mm: a wrist is about 5 cm across"
    near = np.flatnonzero(offsets < low)
    if near.size:
        k = int(near[0])
        return (
            f", {frame(k)}: {marker} is {1000 * offsets[k]:.1f} mm from {axis} "
            f"(it must be {span}), so the forearm's roll is undefined there: is it "
            "on the wrist marker, or on the forearm?",
            k,
        )
    median = float(np.median(offsets))
    odd = np.flatnonzero(
        (np.abs(offsets / median - 1.0) > THUMB_SPREAD) | (offsets > high)
    )
    if not odd.size:
        return None
    k = int(odd[0])
    return (
        f", {frame(k)}: {marker} is {1000 * offsets[k]:.1f} mm from {axis}, its "
        f"median {1000 * median:.1f} mm (it must be {span}): a marker is misplaced "
        "or mislabelled there",
        k,
    )


def check_turns(
    frames: FloatArray,
    times: FloatArray,
    frame: FrameName,
    names: dict[str, str],
    where: str,
    path: str,
    *,
    lines: Lines = None,
) -> None:
    """Refuse a wrist frame that turns between two frames faster than a forearm.

    A turn above ``FASTEST_TURN`` times the step, but at least
    ``LEAST_REFUSED_TURN`` and at most ``MOST_TURN``, is refused.

    Args:
        frames: Wrist frames, shape (n, 3, 3).
        times: Frame times [s], shape (n,).
        frame: Names frame ``k`` for messages.
        names: The markers' names by role (``wrist``, ``thumb``).
        where: The trial named for messages, e.g. ``"subject 'P01', trial 0"``.
        path: The file, for messages.
        lines: Each frame's line in a CSV file (``sample_lines``), for the
            evidence, or ``None``.

    Raises:
        DemoFileError: naming the trial, both frames, the turn and its speed.
    """
    turns = _turns(frames)
    steps = np.diff(times)
    limits = np.clip(FASTEST_TURN * steps, LEAST_REFUSED_TURN, MOST_TURN)
    fast = np.flatnonzero(turns > limits)
    if not fast.size:
        return
    k = int(fast[0])
    degrees = float(np.degrees(turns[k]))
    raise DemoFileError(
        path,
        f"{where}: the wrist frame turns {degrees:.0f} deg from {frame(k)} to "
        f"{frame(k + 1)}, at {degrees / steps[k]:.0f} deg/s: a forearm turns at "
        f"most about {np.degrees(FASTEST_TURN):.0f} deg/s (and a turn over "
        f"{np.degrees(MOST_TURN):.0f} deg between two frames cannot be told from "
        f"a swap): are the markers {names['thumb']!r} and {names['wrist']!r} "
        "swapped there, or one of them misplaced?",
        marker=names["thumb"],
        frame=k + 1,
        turn=degrees,
        **line_evidence(lines, k, k + 1),
    )


def _turns(frames: FloatArray) -> FloatArray:
    """Angle [rad] of the rotation from each frame to the next, shape (n - 1,)."""
    trace = np.einsum("kij,kij->k", frames[:-1], frames[1:])
    return np.asarray(np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0)))
