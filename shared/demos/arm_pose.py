"""A human arm posture as an upper-arm frame, an elbow flexion and a forearm roll.

The posture of a shoulder-elbow-wrist chain, shoulder at the origin:
    frame: rotation matrix whose columns are u (shoulder to elbow, unit),
        n (the elbow's flexion axis, normal to the arm plane) and u x n. Its
        change is what the shoulder does (swing and humeral rotation).
    flexion: elbow flexion beta [rad], 0 with the arm straight; the forearm
        points along f = cos(beta) u + sin(beta) (n x u).
    roll: forearm roll psi [rad] (pronation/supination), 0 with the palm
        facing -n, positive turning the palm about f (right-hand rule).

The wrist frame follows NAO's convention: x along the forearm, y the palm
normal of a right hand (a left hand's palm faces -y), z = x cross y.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from shared.demos.rotations import FloatArray, unit

_UP = np.array([0.0, 0.0, 1.0])


class ArmPose(NamedTuple):
    """One posture (see the module docstring).

    Attributes:
        frame: Upper-arm frame [u, n, u x n], shape (3, 3).
        flexion: Elbow flexion beta [rad].
        roll: Forearm roll psi [rad].
    """

    frame: FloatArray
    flexion: float
    roll: float


class ChainPoints(NamedTuple):
    """Elbow, wrist and wrist frame of postures, shoulder at the origin.

    Attributes:
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        wrist_frame: Wrist frames (x forearm, y palm normal of a right hand),
            shape (n, 3, 3).
    """

    elbow: FloatArray
    wrist: FloatArray
    wrist_frame: FloatArray


def chain_points(
    frames: FloatArray,
    flexion: FloatArray,
    roll: FloatArray,
    upper: float,
    forearm: float,
) -> ChainPoints:
    """Elbow, wrist and wrist frame of n postures.

    Args:
        frames: Upper-arm frames, shape (n, 3, 3).
        flexion: Elbow flexions [rad], shape (n,).
        roll: Forearm rolls [rad], shape (n,).
        upper: Upper arm length L_u [m].
        forearm: Forearm length L_f [m].
    """
    u, n, third = frames[:, :, 0], frames[:, :, 1], frames[:, :, 2]
    cos_b, sin_b = np.cos(flexion)[:, None], np.sin(flexion)[:, None]
    f = cos_b * u - sin_b * third  # n x u = -(u x n)
    elbow = upper * u
    wrist = elbow + forearm * f
    away = -n
    palm = np.cos(roll)[:, None] * away + np.sin(roll)[:, None] * np.cross(f, away)
    frame = np.stack((f, palm, np.cross(f, palm)), axis=-1)
    return ChainPoints(elbow, wrist, frame)


def frame_from_directions(upper_dir: FloatArray, forearm_dir: FloatArray) -> FloatArray:
    """The upper-arm frame [u, n, u x n] of a bent arm, shape (3, 3).

    Args:
        upper_dir: Shoulder-to-elbow direction, shape (3,).
        forearm_dir: Elbow-to-wrist direction, shape (3,), not along ``upper_dir``.
    """
    u = unit(upper_dir)
    n = unit(np.cross(u, forearm_dir))
    return np.stack((u, n, np.cross(u, n)), axis=-1)


def flexion_for_distance(upper: float, forearm: float, distance: float) -> float:
    """Elbow flexion [rad] that puts the wrist ``distance`` m from the shoulder.

    The arm triangle: distance^2 = L_u^2 + L_f^2 + 2 L_u L_f cos(beta).
    """
    cos = (distance**2 - upper**2 - forearm**2) / (2.0 * upper * forearm)
    return math.acos(min(max(cos, -1.0), 1.0))


def elbow_for_target(
    target: FloatArray, upper: float, forearm: float, swivel: float
) -> FloatArray:
    """Elbow position [m], shape (3,), that puts the wrist on ``target``.

    The elbow lies on a circle about the shoulder-target axis; ``swivel`` picks
    the point, measured about that axis from the upward vertical (pi: elbow
    straight down), as ``shared.geometry.swivel`` measures it.

    Args:
        target: Wrist target [m], shape (3,), within reach.
        upper: Upper arm length L_u [m].
        forearm: Forearm length L_f [m].
        swivel: Elbow swivel angle [rad].
    """
    distance = float(np.linalg.norm(target))
    axis = target / distance
    cos_a = (upper**2 + distance**2 - forearm**2) / (2.0 * upper * distance)
    cos_a = min(max(cos_a, -1.0), 1.0)
    centre = upper * cos_a * axis
    radius = upper * math.sqrt(1.0 - cos_a**2)
    vertical = unit(_UP - float(_UP @ axis) * axis)
    side = np.cross(axis, vertical)
    return np.asarray(
        centre + radius * (math.cos(swivel) * vertical + math.sin(swivel) * side),
        dtype=float,
    )


def pose_for_target(
    target: FloatArray, upper: float, forearm: float, swivel: float, roll: float
) -> ArmPose:
    """The posture with the wrist on ``target`` and the given swivel and roll.

    Args:
        target: Wrist target [m], shape (3,), within reach.
        upper: Upper arm length L_u [m].
        forearm: Forearm length L_f [m].
        swivel: Elbow swivel angle [rad] (pi: elbow straight down).
        roll: Forearm roll [rad].
    """
    elbow = elbow_for_target(target, upper, forearm, swivel)
    frame = frame_from_directions(elbow, target - elbow)
    distance = float(np.linalg.norm(target))
    return ArmPose(frame, flexion_for_distance(upper, forearm, distance), roll)
