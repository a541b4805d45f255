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
``DECIMALS`` decimals. Given the trajectory's velocities at the frames
(``bridge.frames.frame_velocities``), every key also holds its tangents
(``bridge.key_tangents``): the slope there, handles a third of the way to
the neighbouring keys, so that the runtime plays the cubic Hermite curve
with the planned slopes between keys; the held last posture's keys are
level. Without velocities the keys have no tangents and the runtime gives
them its own (BezierAuto, ``bridge.bezier_auto``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from bridge.bezier_auto import auto_handles
from bridge.float32 import RANGE_INSET, degrees_as_radians, frame_times, held
from bridge.key_tangents import held_slopes, tangent_handles
from bridge.limits import FrameLimits
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
#: Decimals written for a tangent's abscissa [frames] and ordinate (a third
#: of a frame to float precision).
TANGENT_DECIMALS = 9
#: How far inside its joint's range a key and its tangents' handles are held
#: [rad]: a written angle's last digit, or the rounding to 32 bits on the way
#: to the robot (``bridge.float32.RANGE_INSET``), whichever is more.
KEY_INSET = max(QUANTUM, RANGE_INSET)
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
        left: Each key's left tangent as written: its handle's offset from
            the key, n arrays of shape (m_i, 2): abscissa [frames] and
            ordinate [the values' unit]; ``None``: keys without tangents,
            which the runtime gives BezierAuto ones (:meth:`handles`).
        right: Each key's right tangent, likewise.
    """

    fps: int
    names: list[str]
    frames: list[np.ndarray]
    values: list[np.ndarray]
    start_frame: int = START_FRAME
    left: list[np.ndarray] | None = None
    right: list[np.ndarray] | None = None

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

    def handles(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """``name``'s left and right handles as the runtime plays them, each (m, 2).

        Abscissa [frames] and ordinate [the values' unit], offsets from the
        key: as written, or for keys without tangents the runtime's
        BezierAuto ones (``bridge.bezier_auto.auto_handles``).
        """
        j = self.names.index(name)
        if self.left is not None and self.right is not None:
            return self.left[j], self.right[j]
        left, right = auto_handles(self.frames[j], self.values[j][:, None])
        return left[:, 0], right[:, 0]

    def slopes(self, name: str) -> np.ndarray:
        """Slopes of ``name``'s handles in SI, shape (m, 2): left, right.

        Ordinate over abscissa per second [rad/s; /s for a hand]; 0 for a
        handle of no length (the first key's left, the last key's right).
        """
        fps = float(self.fps)
        per_frame = np.column_stack([_slope(handle) for handle in self.handles(name)])
        return fps * (per_frame if is_hand(name) else np.radians(per_frame))


def _slope(handle: np.ndarray) -> np.ndarray:
    """Ordinate over abscissa of handles (shape (m, 2)), 0 where the abscissa is."""
    x, y = handle[:, 0], handle[:, 1]
    return np.where(x != 0.0, y / np.where(x != 0.0, x, 1.0), 0.0)


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


def timeline_keys(
    frames: CommandFrames, velocities: npt.ArrayLike | None = None
) -> TimelineKeys:
    """The keys a behavior's timeline holds for ``frames`` (see the module).

    Args:
        frames: Command frames on frames ``1..m`` of their timeline, at a
            whole number of frames per second.
        velocities: Slopes at frame 0 and at each frame [rad/s; /s for a
            hand], shape (m + 1, n): the trajectory's velocities there
            (``bridge.frames.frame_velocities``). ``None``: keys without
            tangents.

    Returns:
        One curve per joint: the start at ``START_FRAME``, frame ``k`` at
        ``START_FRAME + k``, then the hold; values and tangents as written.

    Raises:
        InvalidInputError: the rate is not a whole number (``timeline_fps``),
            ``velocities`` has not one row per key of the frames, or (with
            velocities) a joint has no known range.
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
    numbered = [keyed.copy() for _ in names]
    if velocities is None:
        return TimelineKeys(fps, names, numbered, values)
    slopes = _key_slopes(frames, velocities, hold) / fps
    left, right = _tangents(frames, keyed, np.column_stack(values), slopes)
    return TimelineKeys(fps, names, numbered, values, START_FRAME, left, right)


def _key_slopes(
    frames: CommandFrames, velocities: npt.ArrayLike, hold: int
) -> np.ndarray:
    """Slopes at every key [rad/s; /s], shape (m + 1 + hold, n); the hold is level."""
    speeds = np.asarray(velocities, dtype=float)
    shape = (len(frames.times) + 1, len(frames.joint_names))
    if speeds.shape != shape or not np.isfinite(speeds).all():
        raise InvalidInputError(
            f"velocities of shape {speeds.shape} for frames of shape {shape}: "
            "give one finite row for the start and one per frame",
            field="velocities",
        )
    return np.vstack([speeds, np.zeros((hold, shape[1]))])


def _tangents(
    frames: CommandFrames, keyed: np.ndarray, written: np.ndarray, slopes: np.ndarray
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Each curve's left and right tangents as written, n arrays of shape (m, 2).

    Args:
        frames: The frames (arm, joints).
        keyed: Frame numbers of the keys, shape (m,).
        written: The keys' values as written, shape (m, n).
        slopes: Slopes at the keys [rad per frame; per frame], shape (m, n).
    """
    scale = np.array(
        [1.0 if is_hand(n) else math.degrees(1.0) for n in frames.joint_names]
    )
    lower, upper = key_ranges(frames)
    held_slope = held_slopes(
        keyed, written, slopes * scale, lower * scale, upper * scale
    )
    left, right = tangent_handles(keyed, held_slope)
    return _as_written(left), _as_written(right)


def _as_written(handles: np.ndarray) -> list[np.ndarray]:
    """Handles (shape (m, n, 2)) as the file writes them, one (m, 2) array a curve."""
    text = np.char.mod(f"%.{TANGENT_DECIMALS}f", handles)
    numbers = text.astype(float) + 0.0  # no -0.0
    return [numbers[:, j, :] for j in range(handles.shape[1])]


def key_ranges(frames: CommandFrames) -> tuple[np.ndarray, np.ndarray]:
    """Where ``frames``' keys and handles are held [rad; fraction], each shape (n,).

    The joints' ranges (``bridge.limits.FrameLimits`` of the frames' arm,
    with its hand if they move it), ``KEY_INSET`` inside.

    Raises:
        InvalidInputError: a joint that is not one of the arm's or its hand.
    """
    limits = FrameLimits.for_arm(frames.arm)
    if any(is_hand(name) for name in frames.joint_names):
        limits = limits.with_hand(frames.arm)
    unknown = [n for n in frames.joint_names if n not in limits.names]
    if unknown:
        raise InvalidInputError(
            f"no range is known for {unknown}: the frames of the {frames.arm.value} "
            f"arm move {list(limits.names)}",
            field="joint_names",
        )
    index = [limits.names.index(name) for name in frames.joint_names]
    return limits.lower[index] + KEY_INSET, limits.upper[index] - KEY_INSET


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
