"""NAO's own body as the arm must keep clear of it: torso, pelvis and head.

The robot description (``nao_arms.urdf``) holds the arms' kinematics but no
shapes, and Aldebaran publishes none for its self-collision model (spheres
and capsules, its documentation says, without their sizes). The shapes here
are those of the NAO H25 model of the Webots simulator (Cyberbotics, "made
according to the documentation provided by Aldebaran"), in NAOqi's
FRAME_TORSO (x forward, y left, z up) [m]:

- torso: a capsule of radius 55 mm around the segment from z = 40 mm to
  z = 70 mm (it reaches from z = -15 mm to 125 mm, 55 mm to every side; the
  chest's surface lies 53-58 mm ahead of the axis);
- pelvis: a ball of radius 37 mm at z = -20 mm;
- head: Webots' head is a capsule of radius 50 mm, 40 mm long across the
  head, 55 mm above the neck joint (z = 126.5 mm). The head turns
  (HeadYaw, ±119.5 degrees), which armplan does not command or know, so
  the shape here is every way it can turn: a ball of radius 70 mm at
  z = 181.5 mm. A head pitched forward or back (HeadPitch) moves its face
  up to 34 mm ahead of or behind that ball: not in the model.

The arm is three capsules between the points of :class:`ArmPoints`: the
upper arm (shoulder to elbow, radius ``UPPER_ARM``), the forearm (elbow to
wrist, ``FOREARM``) and the hand (wrist to the gripper frame, ``HAND``), the
radii of the same Webots model (upper arm 24 mm, elbow 20 mm, forearm
22 mm, the hand's 30 mm cylinder). An arm part is clear of a body part
when their surfaces are ``MARGIN`` apart or more.

The other arm is kept clear of where it is by the bridge, which reads it
(:func:`other_arm`). Not in the model: the legs (where they are depends on
the robot's stance: crouched, NAO's thighs lie under its hands), and
anything around the robot.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from shared.errors import BodyCollisionError, TargetInBodyError
from shared.geometry.segments import segment_distance
from shared.robot.arm_model import ArmModel
from shared.robot.fk_many import key_points

#: Least distance kept between the arm's surface and the body's [m]: the
#: shapes are a few millimetres rough (the chest's surface lies up to 3 mm
#: outside the torso capsule). The frames sent to the robot are checked
#: themselves (``bridge.body_clearance``); between two frames, 20 ms apart
#: at most at NAO's cycle, the arm moves a few millimetres at most.
MARGIN = 0.005
#: Radii of the arm's capsules [m].
UPPER_ARM = 0.024
FOREARM = 0.022
HAND = 0.030


class BodyPart(NamedTuple):
    """A capsule (a ball when both ends are one point) fixed to the torso.

    Attributes:
        name: What it is, e.g. ``"torso"``.
        bottom: One end of its segment [m], shape (3,).
        top: The other end [m], shape (3,).
        radius: Its radius [m].
    """

    name: str
    bottom: tuple[float, float, float]
    top: tuple[float, float, float]
    radius: float


#: NAO's torso, pelvis and head in the torso frame (see the module's text).
BODY: tuple[BodyPart, ...] = (
    BodyPart("torso", (0.0, 0.0, 0.040), (0.0, 0.0, 0.070), 0.055),
    BodyPart("pelvis", (0.0, 0.0, -0.020), (0.0, 0.0, -0.020), 0.037),
    BodyPart("head", (0.0, 0.0, 0.1815), (0.0, 0.0, 0.1815), 0.070),
)

#: The arm's parts: name, the ends' names in ``ArmPoints``, and radius [m].
ARM_PARTS: tuple[tuple[str, str, str, float], ...] = (
    ("upper arm", "shoulder", "elbow", UPPER_ARM),
    ("forearm", "elbow", "wrist", FOREARM),
    ("hand", "wrist", "hand", HAND),
)


#: The arm parts' radii [m], shape (A,), in ``ARM_PARTS``' order.
ARM_RADII = np.array([radius for *_, radius in ARM_PARTS])


class Closest(NamedTuple):
    """Where an arm comes nearest to the body.

    Attributes:
        sample: The posture (row of the postures given).
        arm_part: ``"upper arm"``, ``"forearm"`` or ``"hand"``.
        body_part: ``"torso"``, ``"pelvis"`` or ``"head"``.
        clearance: Distance between their surfaces [m]; negative: that
            deep inside.
    """

    sample: int
    arm_part: str
    body_part: str
    clearance: float


def arm_points(arm: ArmModel, q: npt.ArrayLike) -> dict[str, np.ndarray]:
    """The arm's key points [m] for postures ``q`` [rad], shape (n, 5).

    Returns:
        ``ArmPoints``' fields, each shape (n, 3) (``shared.robot.fk_many``).
    """
    return key_points(arm, q)


def clearances(
    points: dict[str, np.ndarray], parts: tuple[BodyPart, ...] = BODY
) -> np.ndarray:
    """Distance [m] between each arm part's surface and each body part's.

    Args:
        points: The arm's key points (:func:`arm_points`), each shape (n, 3).
        parts: What to keep clear of; default NAO's body (``BODY``), or
            that and the other arm (:func:`other_arm`).

    Returns:
        Shape (n, len(ARM_PARTS), len(parts)); negative: overlapping.
    """
    bottom, top, radii = _capsules(parts)
    starts = np.stack([points[first] for _, first, _, _ in ARM_PARTS], axis=1)
    ends = np.stack([points[last] for _, _, last, _ in ARM_PARTS], axis=1)
    between = segment_distance(starts[:, :, None], ends[:, :, None], bottom, top)
    return between - ARM_RADII[:, None] - radii  # (n, A, P), one call for all


@functools.lru_cache(maxsize=64)
def _capsules(parts: tuple[BodyPart, ...]) -> tuple[np.ndarray, ...]:
    """``parts``' ends [m], each shape (P, 3), and radii [m], shape (P,).

    Kept for the parts asked last (read-only): ``BODY`` and the other arm
    held still are asked again at every check of a plan.
    """
    arrays = (
        np.array([part.bottom for part in parts], dtype=float).reshape(-1, 3),
        np.array([part.top for part in parts], dtype=float).reshape(-1, 3),
        np.array([part.radius for part in parts], dtype=float),
    )
    for array in arrays:
        array.flags.writeable = False
    return arrays


def closest(
    arm: ArmModel, q: npt.ArrayLike, parts: tuple[BodyPart, ...] = BODY
) -> Closest:
    """Where the postures ``q`` [rad], shape (n, 5), come nearest ``parts``."""
    gaps = clearances(arm_points(arm, q), parts)
    return _at(gaps, int(np.argmin(gaps.min(axis=(1, 2)))), parts)


def first_near(
    arm: ArmModel,
    q: npt.ArrayLike,
    margin: float = MARGIN,
    parts: tuple[BodyPart, ...] = BODY,
) -> Closest | None:
    """The first posture of ``q`` [rad], (n, 5), nearer ``parts`` than ``margin`` [m].

    Returns:
        Where it is nearest, or None if every posture keeps ``margin``.
    """
    gaps = clearances(arm_points(arm, q), parts)
    near = np.flatnonzero(~(gaps.min(axis=(1, 2)) >= margin))  # NaN: near
    return None if near.size == 0 else _at(gaps, int(near[0]), parts)


def _at(gaps: np.ndarray, sample: int, parts: tuple[BodyPart, ...]) -> Closest:
    """The arm's part and the part of ``parts`` nearest each other in ``sample``."""
    arm_part, body_part = np.unravel_index(int(np.argmin(gaps[sample])), gaps.shape[1:])
    return Closest(
        sample=sample,
        arm_part=ARM_PARTS[arm_part][0],
        body_part=parts[body_part].name,
        clearance=float(gaps[sample, arm_part, body_part]),
    )


def other_arm(arm: ArmModel, q: npt.ArrayLike) -> tuple[BodyPart, ...]:
    """The arm of ``arm``'s posture ``q`` [rad], (5,), as parts to keep clear of.

    Its capsules are the arm's own (``ARM_PARTS``), named with its side
    (``"left forearm"``): what the other arm must keep clear of while this
    one holds still.
    """
    points = arm_points(arm, np.atleast_2d(np.asarray(q, dtype=float)))
    return tuple(
        BodyPart(
            f"{arm.side.value} {name}",
            _point(points[first][0]),
            _point(points[last][0]),
            radius,
        )
        for name, first, last, radius in ARM_PARTS
    )


def _point(v: np.ndarray) -> tuple[float, float, float]:
    return float(v[0]), float(v[1]), float(v[2])


def point_clearance(
    point: npt.ArrayLike, radius: float, parts: tuple[BodyPart, ...] = BODY
) -> tuple[str, float]:
    """The part of ``parts`` nearest a ball of ``radius`` [m] at ``point`` [m], (3,).

    Returns:
        That part's name and the distance between the surfaces [m].
    """
    names, gaps = points_clearance(np.reshape(point, (1, 3)), radius, parts)
    return names[0], float(gaps[0])


def points_clearance(
    points: npt.ArrayLike, radius: float, parts: tuple[BodyPart, ...] = BODY
) -> tuple[list[str], np.ndarray]:
    """The part of ``parts`` nearest each ball of ``radius`` [m] at ``points`` [m].

    Args:
        points: The balls' centres [m], shape (n, 3).
        radius: Their radius [m].
        parts: What to keep clear of; default NAO's body.

    Returns:
        Each one's nearest part, and the distances between the surfaces [m],
        shape (n,).
    """
    centres = np.asarray(points, dtype=float)[:, None, :]
    bottom, top, radii = _capsules(parts)
    gaps = segment_distance(centres, centres, bottom, top) - radius - radii
    nearest = np.argmin(gaps, axis=1)
    return [parts[k].name for k in nearest], gaps.min(axis=1)


def first_point_near(
    points: npt.ArrayLike, parts: tuple[BodyPart, ...] = BODY
) -> int | None:
    """The first of ``points`` [m], (n, 3), no wrist may reach: none if None.

    A wrist there puts the hand's ball (``HAND``) nearer ``parts`` (default
    NAO's body) than ``MARGIN``, whatever the posture
    (:func:`check_target_clear`).
    """
    _, gaps = points_clearance(points, HAND, parts)
    near = np.flatnonzero(~(gaps >= MARGIN))  # NaN: near
    return None if near.size == 0 else int(near[0])


def check_target_clear(
    arm: ArmModel,
    target: npt.ArrayLike,
    at: str = "",
    parts: tuple[BodyPart, ...] = BODY,
) -> None:
    """Raise if no posture with its wrist at ``target`` [m], (3,), keeps clear.

    The hand's capsule ends at the wrist in a ball of radius ``HAND``: if that
    ball comes nearer ``parts`` (default NAO's body) than ``MARGIN``, so does
    every posture.

    Raises:
        TargetInBodyError: naming the part and how near it is.
    """
    position = np.asarray(target, dtype=float)
    part, gap = point_clearance(position, HAND, parts)
    if not gap >= MARGIN:  # NaN: refused
        shape = next(each for each in parts if each.name == part)
        own = float(segment_distance(position, position, shape.bottom, shape.top))
        shoulder = arm.fk(np.zeros(5)).shoulder
        raise TargetInBodyError(
            position,
            arm=arm.side.value,
            distance=float(np.linalg.norm(position - shoulder)),
            reach=arm.reach,
            body_part=part,
            clearance=gap,
            margin=MARGIN,
            at=at,
            inside=own < shape.radius,
        )


def check_start_clear(
    arm: ArmModel,
    start: npt.ArrayLike,
    what: str = "the start posture",
    advice: str = "move the arm away from the body first, or give another start",
    parts: tuple[BodyPart, ...] = BODY,
) -> None:
    """Raise if the posture a plan starts from comes nearer ``parts`` than ``MARGIN``.

    ``parts``: default NAO's body.

    Raises:
        BodyCollisionError: naming the parts nearest each other (index 0).
    """
    near = first_near(arm, np.atleast_2d(np.asarray(start, dtype=float)), parts=parts)
    if near is not None:
        raise collision_error(
            arm,
            near,
            0.0,
            what=what,
            at="",
            advice=f"nothing was planned: {advice}",
        )


def check_postures_clear(
    arm: ArmModel,
    q: npt.ArrayLike,
    times: npt.ArrayLike,
    what: str = "the planned movement",
    parts: tuple[BodyPart, ...] = BODY,
    advice: str = "",
) -> None:
    """Raise if a posture of ``q`` [rad], (n, 5), comes nearer the body than ``MARGIN``.

    Args:
        arm: The arm.
        q: The postures.
        times: Their times [s], shape (n,); the error counts from the first.
        what: What the postures are, for the error.
        parts: What to keep clear of (default NAO's body).
        advice: What the error advises; "" for ``BodyCollisionError``'s own.

    Raises:
        BodyCollisionError: naming the first such posture, its time, and
            the arm's and the body's parts nearest each other in it.
    """
    near = first_near(arm, q, parts=parts)
    if near is not None:
        clock = np.asarray(times, dtype=float)
        words = {"what": what, "advice": advice} if advice else {"what": what}
        raise collision_error(arm, near, float(clock[near.sample] - clock[0]), **words)


def collision_error(
    arm: ArmModel, near: Closest, time: float, **words: str
) -> BodyCollisionError:
    """The error for ``near``, posture ``near.sample`` at ``time`` [s]."""
    return BodyCollisionError(
        arm=arm.side.value,
        arm_part=near.arm_part,
        body_part=near.body_part,
        clearance=near.clearance,
        margin=MARGIN,
        index=near.sample,
        time=time,
        **words,
    )
