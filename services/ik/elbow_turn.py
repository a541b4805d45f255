"""Turning NAO's elbow about the line from the shoulder to the wrist.

The arm keeps its wrist where it is when the elbow turns about that line
(the elbow's swivel: the paper's function primitive S_R E_P W_R, "obstacle
avoidance movements" with the wrist fixed). With NAO's elbow offset the
four arm joints that put the turned elbow there, the wrist in place, are
found by least squares within their ranges
(``shared.demos.posture_from_points``). The planner turns a reach's elbow
this way to go round NAO's body (``services.planner.clear_swivel``), and
the ik answer's posture likewise (``services.ik.solver``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from services.ik.iterate import TOLERANCE
from shared.demos.posture_from_points import joints_from_points
from shared.geometry.palm import roll_error
from shared.robot.arm_model import ArmModel
from shared.robot.body import BODY, MARGIN, BodyPart, clearances
from shared.robot.fk_many import key_points

WRIST_YAW = 4
#: Clearance a turned arm aims for [m]: twice the margin, so that the
#: timing's curve between a path's points stays clear too.
AIM = 2.0 * MARGIN
#: Swivels tried, each way, smallest first [rad].
SWIVELS = (0.1, 0.2, 0.35, 0.5, 0.7, 1.0, 1.4)


class Turned(NamedTuple):
    """A joint path with the elbow turned.

    Attributes:
        positions: Joint angles [rad], shape (n, 5).
        least: Its least clearance from the body [m].
    """

    positions: np.ndarray
    least: float


def turn_elbow(
    arm: ArmModel,
    q: np.ndarray,
    swivel: np.ndarray,
    palm: Sequence[float] | np.ndarray | None,
    stride: int = 1,
    parts: tuple[BodyPart, ...] = BODY,
) -> Turned | None:
    """The postures ``q`` [rad], (n, 5), with the elbow turned by ``swivel`` [rad].

    Each sample's elbow turns by its swivel about the line from the shoulder
    to the wrist (right-handed); the four arm joints that put it there with
    the wrist in place are solved within their ranges from the sample's own
    posture. A wanted ``palm`` keeps its roll error (WristYaw turns by what
    the swivel changed of it, stopping at its range on the way); else
    WristYaw stays.

    With ``stride`` over 1 only every ``stride``-th sample with a swivel
    (and the last one) is turned and measured: a quick screen.

    Returns:
        The turned postures and their least clearance (over the samples
        turned, with a stride), or None if a sample's wrist moved more than
        the IK's tolerance or the goal's WristYaw would leave its range (the
        palm would miss its roll there).
    """
    points = key_points(arm, q)
    out = q.copy()
    low, high = arm.limits.lower[WRIST_YAW], arm.limits.upper[WRIST_YAW]
    turn = np.flatnonzero(swivel)
    if stride > 1:
        turn = np.union1d(turn[::stride], turn[-1:])
    change = 0.0  # the roll change of the sample before, to unwrap from
    for i in turn:
        shoulder, wrist = points["shoulder"][i], points["wrist"][i]
        elbow = shoulder + rotate(
            points["elbow"][i] - shoulder, wrist - shoulder, swivel[i]
        )
        turned = joints_from_points(arm, elbow, wrist, guess=q[i])
        if palm is not None:
            change += _roll_change(arm, q[i], turned, palm, change)
            turned[WRIST_YAW] += change
        if not low <= turned[WRIST_YAW] <= high:
            if i == len(q) - 1:
                return None  # the palm would miss its roll at the goal
            turned[WRIST_YAW] = min(max(turned[WRIST_YAW], low), high)
        out[i] = turned
    measured = turn if stride > 1 else np.arange(len(q))
    moved = np.linalg.norm(
        key_points(arm, out[measured])["wrist"] - points["wrist"][measured], axis=1
    )
    if not bool(np.all(moved <= TOLERANCE)):
        return None
    return Turned(out, float(least_clearances(arm, out[measured], parts).min()))


def rotate(v: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    """``v`` [m], (3,), turned by ``angle`` [rad] about ``axis`` (Rodrigues)."""
    k = axis / np.linalg.norm(axis)
    return (
        v * math.cos(angle)
        + np.cross(k, v) * math.sin(angle)
        + k * float(k @ v) * (1.0 - math.cos(angle))
    )


def _roll_change(
    arm: ArmModel,
    before: np.ndarray,
    after: np.ndarray,
    palm: Sequence[float] | np.ndarray,
    near: float,
) -> float:
    """The WristYaw turn [rad] keeping ``before``'s palm roll error in ``after``.

    Less ``near`` and within half a turn of 0: the turn nearest ``near``
    (the sample before's), so that WristYaw does not jump a turn between
    samples where the roll wraps round.
    """
    sign = arm.side.sign
    change = roll_error(arm.rotation(after, "wrist"), sign, palm) - roll_error(
        arm.rotation(before, "wrist"), sign, palm
    )
    return math.remainder(change - near, 2.0 * math.pi)


def least_clearances(
    arm: ArmModel, q: np.ndarray, parts: tuple[BodyPart, ...] = BODY
) -> np.ndarray:
    """Each posture's least clearance from ``parts`` [m], shape (n,); NaN: -inf."""
    gaps = clearances(key_points(arm, q), parts).min(axis=(1, 2))
    return np.where(np.isnan(gaps), -np.inf, gaps)


def turned_clear(
    arm: ArmModel,
    q: np.ndarray,
    palm: Sequence[float] | np.ndarray | None,
    parts: tuple[BodyPart, ...] = BODY,
) -> np.ndarray | None:
    """The posture ``q`` [rad], (5,), turned about its wrist to keep clear of ``parts``.

    The smallest of ``SWIVELS`` (each way) that keeps ``AIM`` from
    ``parts`` (default NAO's body), else the one that keeps ``MARGIN`` with
    most room; a wanted ``palm`` keeps its roll.

    Returns:
        The turned posture, shape (5,), or None if no swivel tried keeps
        ``MARGIN``.
    """
    posture = np.asarray(q, dtype=float)[None, :]
    best: Turned | None = None
    for size in SWIVELS:
        for sign in (1.0, -1.0):
            turned = turn_elbow(
                arm, posture, np.array([sign * size]), palm, parts=parts
            )
            if turned is None or not turned.least >= MARGIN:
                continue
            if turned.least >= AIM:
                return turned.positions[0]
            if best is None or turned.least > best.least:
                best = turned
    return None if best is None else best.positions[0]
