"""Smooth joint trajectories through postures, for trying the bridge without a planner.

Each segment between two postures follows the minimum-jerk profile
``q = q0 + (q1 - q0) (10 s^3 - 15 s^4 + 6 s^5)``, ``s = t / T``, which starts
and ends at rest: its peak speed is ``PEAK_SPEED |q1 - q0| / T``, its peak
acceleration ``PEAK_ACCELERATION |q1 - q0| / T^2`` and its peak jerk
``PEAK_JERK |q1 - q0| / T^3``.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from shared.messages import Trajectory
from shared.robot import Side, load_arm

#: Peaks of the blend's first three derivatives in s over [0, 1]: 15/8 at
#: s = 1/2, 10/sqrt(3) at s = 1/2 -+ sqrt(3)/6, and 60 at both ends.
PEAK_SPEED, PEAK_ACCELERATION, PEAK_JERK = 1.875, 10.0 / math.sqrt(3.0), 60.0


def minimum_jerk_blend(s: np.ndarray) -> np.ndarray:
    """``10 s^3 - 15 s^4 + 6 s^5``: 0 at s = 0, 1 at s = 1, at rest at both [-]."""
    return s**3 * (10.0 - 15.0 * s + 6.0 * s**2)


def _profile(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum-jerk blend and its first two derivatives in ``s``, each (k,)."""
    blend = minimum_jerk_blend(s)
    speed = 30 * s**2 - 60 * s**3 + 30 * s**4
    accel = 60 * s - 180 * s**2 + 120 * s**3
    return blend, speed, accel


def minimum_jerk_trajectory(
    arm: Side | str,
    postures: npt.ArrayLike,
    durations: npt.ArrayLike,
    rate: float = 100.0,
) -> Trajectory:
    """A trajectory through ``postures``, at rest at each one.

    Args:
        arm: Which arm.
        postures: Joint angles to pass through [rad], shape (p, 5), p >= 2.
        durations: Time of each segment [s], shape (p - 1,).
        rate: Sample rate [Hz].

    Returns:
        The trajectory, with its wrist path from forward kinematics [m] and
        every sample labelled with the all-joints primitive "S_R E_PR W_PR".
    """
    side = Side.parse(arm)
    q = np.asarray(postures, dtype=float)
    spans = np.asarray(durations, dtype=float)
    times, pos, vel, acc = (
        [np.zeros(1)],
        [q[:1]],
        [np.zeros((1, 5))],
        [np.zeros((1, 5))],
    )
    offset = 0.0
    for a, b, span in zip(q[:-1], q[1:], spans, strict=True):
        t = np.arange(1, round(span * rate) + 1) / rate
        blend, speed, accel = _profile(t / t[-1])
        delta = b - a
        times.append(offset + t)
        pos.append(a + blend[:, None] * delta)
        vel.append(speed[:, None] * delta / t[-1])
        acc.append(accel[:, None] * delta / t[-1] ** 2)
        offset += t[-1]
    positions = np.vstack(pos)
    model = load_arm(side)
    wrist = [tuple(model.fk(row).wrist.tolist()) for row in positions]
    return Trajectory(
        arm=side,
        joint_names=list(side.joint_names),
        times=np.concatenate(times).tolist(),
        positions=positions.tolist(),
        velocities=np.vstack(vel).tolist(),
        accelerations=np.vstack(acc).tolist(),
        primitives=["S_R E_PR W_PR"] * len(positions),
        wrist_path=wrist,
    )
