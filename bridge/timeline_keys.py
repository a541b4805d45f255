"""The keys of a Choregraphe timeline, and when its runtime plays them.

Choregraphe's runtime (libqicore-compat ``timeline.cpp``,
``TimelinePrivate::prepareInterpolationCommand``) sends a timeline's keys
to ALMotion in one ``angleInterpolationBezier`` call, a key at ``frame``
at ``(frame - start_frame) / fps`` seconds after the call: the key at
``start_frame`` at 0 s, the next frame one period later. Choregraphe's
own Python export writes the same times (a key at frame 11 of a 25 fps
timeline starting at frame 1 at 0.4 s).

An armplan behavior's timeline (:func:`timeline_keys`) therefore holds:

- the start posture (the frames' frame 0) at ``START_FRAME``, played at
  0 s: the arm is there already (the behavior's script box brings it,
  ``bridge.choregraphe``) and the curve sets off from rest there;
- frame ``k`` of the command frames at ``START_FRAME + k``, played at
  ``k / fps``: the time the bridge's checks assumed;
- the last posture held for ``hold_frames`` more frames: the runtime steps
  its timeline every ``1000 // fps`` whole milliseconds and stops the
  motion (``ALMotion.stop``) when it reaches the last key's frame, which at
  a rate that does not divide 1000 (30 fps: 33 ms instead of 33.3) comes
  before the last key is played; the hold puts that stop at least
  ``END_MARGIN`` after the last frame, with the arm at rest.

Every value is what the file holds: degrees (a hand's open fraction) with
``DECIMALS`` decimals.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from bridge.float32 import degrees_as_radians, frame_times, held
from shared.errors import InvalidInputError
from shared.messages import CommandFrames

#: Frame of a timeline's first key: Choregraphe numbers frames from 1.
START_FRAME = 1
#: Decimals written for each key's value (1e-6 degree: rounding to 1e-4
#: degree alone made a 1000 fps timeline's jerk 3.6 times the bridge's limit).
DECIMALS = 6
#: The smallest step of a written angle [rad]: frames are held this far
#: inside the joints' ranges, so that rounding never puts one outside.
QUANTUM = math.radians(10.0**-DECIMALS)
#: Least time the last posture is held past the last frame before the
#: runtime's end of the timeline stops the motion [s]: five of ALMotion's
#: 20 ms cycles, for a motion that starts a cycle after it is sent.
END_MARGIN = 0.1


class TimelineKeys(NamedTuple):
    """The keys of a Choregraphe timeline.

    Attributes:
        fps: Frame rate of the timeline [Hz], a whole number as the runtime
            reads it.
        names: Actuators in file order, shape (n,).
        frames: Frame numbers of each actuator's keys, n arrays of shape (m_i,).
        values: Values of those keys as written (degrees, or fraction for a
            hand), n arrays of shape (m_i,).
        start_frame: The timeline's first frame, played at 0 s.
    """

    fps: int
    names: list[str]
    frames: list[np.ndarray]
    values: list[np.ndarray]
    start_frame: int = START_FRAME

    def times(self, name: str) -> np.ndarray:
        """When ``name``'s keys are played, from the timeline's start [s], (m,).

        ``(frame - start_frame) / fps``, as the runtime sends them.
        """
        frames = self.frames[self.names.index(name)]
        return (frames - self.start_frame) / self.fps

    def angles(self, name: str) -> np.ndarray:
        """``name``'s keys in SI: radians for a joint, fraction for a hand."""
        values = self.values[self.names.index(name)]
        return values if is_hand(name) else np.radians(values)


def is_hand(name: str) -> bool:
    """Whether actuator ``name`` is a hand (its curve is an open fraction)."""
    return name.endswith("Hand")


def shown(name: str, values: np.ndarray) -> list[str]:
    """A curve's values [rad] as the file writes them: degrees (fraction for a hand)."""
    held = values if is_hand(name) else np.degrees(values)
    return [f"{v:.{DECIMALS}f}" for v in held]


def timeline_fps(rate: float, what: str = "the frame rate") -> int:
    """``rate`` [Hz] as a Choregraphe timeline's ``fps``: a whole number.

    Choregraphe's runtime holds a timeline's fps as an ``int``
    (libqicore-compat ``AnimationModel``: ``int _fps`` read by
    ``getAttribute("fps", _fps)``; ``Timeline::setFPS(int)``; a frame every
    ``1000 / fps`` ms): ``fps="12.5"`` would not play at the times checked
    (read as 12, or not at all and the default used). The Python export
    keeps any rate.

    Args:
        rate: The frame rate asked for [Hz].
        what: How the message names it (``--rate`` for the command line).

    Raises:
        InvalidInputError: ``rate`` is not a whole number, shown as given.
    """
    rate = float(rate)
    if rate.is_integer():
        return int(rate)
    near = (
        f": use {max(1, math.floor(rate))} or {math.ceil(rate)} fps"
        if math.isfinite(rate)
        else ""
    )
    raise InvalidInputError(
        f"{what} of a Choregraphe behavior must be a whole number of frames "
        f"per second (its runtime holds fps as an int), got {rate!r}{near}, "
        "or export python, which keeps any rate",
        field="rate",
        rate=rate,
    )


def hold_frames(count: int, fps: int) -> int:
    """Frames the last posture is held after ``count`` frames at ``fps``.

    The runtime reaches the last key's frame ``count + hold`` periods of
    ``1000 // fps`` ms after it sent the keys; that must be ``END_MARGIN``
    or more after the last frame, ``count / fps`` s (at least one frame).
    """
    period_ms = 1000 // fps
    needed_ms = 1000.0 * (count / fps + END_MARGIN)
    return max(1, math.ceil(needed_ms / period_ms - 1e-9) - count)


def timeline_keys(frames: CommandFrames) -> TimelineKeys:
    """The keys a behavior's timeline holds for ``frames`` (see the module).

    Args:
        frames: Command frames on frames ``1..m`` of their timeline, at a
            whole number of frames per second.

    Returns:
        One curve per joint: the start at ``START_FRAME``, frame ``k`` at
        ``START_FRAME + k``, then the hold; values as written.

    Raises:
        InvalidInputError: the rate is not a whole number (``timeline_fps``).
    """
    fps = timeline_fps(frames.rate)
    numbers = np.asarray(frames.frame_numbers)
    hold = hold_frames(int(numbers[-1]), fps)
    last = numbers[-1] + np.arange(1, hold + 1)
    keyed = START_FRAME + np.concatenate([[0], numbers, last])
    rows = np.vstack(
        [
            np.asarray(frames.start)[None, :],
            np.asarray(frames.positions),
            np.repeat(np.asarray(frames.positions)[-1:], hold, axis=0),
        ]
    )
    values = [
        np.array(shown(name, rows[:, j]), dtype=float)
        for j, name in enumerate(frames.joint_names)
    ]
    names = list(frames.joint_names)
    return TimelineKeys(fps, names, [keyed.copy() for _ in names], values)


def played_frames(keys: TimelineKeys, frames: CommandFrames) -> CommandFrames:
    """``keys`` as command frames, as the runtime plays them.

    The start posture is the key at ``start_frame``, frame ``k`` the key
    played ``k / fps`` after it (the hold included), every angle and time
    computed in 32-bit floats as the runtime does (``bridge.float32``).

    Args:
        keys: A timeline whose curves all have keys on the same frames, the
            first at ``start_frame``, with ``frames``' joints in order.
        frames: The frames they were made from (arm, joints).

    Raises:
        InvalidInputError: the curves are not keyed alike from ``start_frame``.
    """
    numbers = keys.frames[0]
    if keys.names != list(frames.joint_names) or any(
        not np.array_equal(f, numbers) for f in keys.frames
    ):
        raise InvalidInputError(
            "the timeline's curves are not the frames' joints keyed on the same frames",
            field="keys",
        )
    if numbers[0] != keys.start_frame:
        raise InvalidInputError(
            f"the timeline has no key at its start frame {keys.start_frame}",
            field="keys",
        )
    angles = np.column_stack(
        [
            values if is_hand(name) else degrees_as_radians(values)
            for name, values in zip(keys.names, keys.values, strict=True)
        ]
    )
    played = frame_times(numbers - keys.start_frame, keys.fps)
    return CommandFrames(
        arm=frames.arm,
        rate=keys.fps,
        joint_names=keys.names,
        start=held(angles[0]).tolist(),
        times=played[1:].tolist(),
        positions=held(angles[1:]).tolist(),
    )


def behavior_frames(frames: CommandFrames) -> CommandFrames:
    """``frames`` as a behavior's timeline plays them (:func:`timeline_keys`).

    This is what Choregraphe plays, so it is what the bridge's checks must
    pass (``bridge.check_behavior``): each value rounded as written, the
    last posture held.
    """
    return played_frames(timeline_keys(frames), frames)
