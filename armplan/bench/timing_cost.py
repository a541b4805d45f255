"""Cost of the timing beside toppra's time-optimal parameterisation, same path.

The path: the joint path of a one-second reach sampled at 100 Hz (101
points), as the planner makes it: a minimum-jerk wrist path from the arm at
rest to a target, followed by the IK (services/ik/track.py) with the full
reaching primitive. Both time it from rest to rest with the same speed and
acceleration limits; ours also keeps the jerk limits, which toppra has no
constraint for (its result may exceed them). Each is timed end to end,
including sampling the result at 100 Hz.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from armplan.bench.timer import Timing, time_calls
from services.ik.track import track_path
from services.planner.wrist_path import reach_path
from services.timing import reach_duration, time_path
from shared.primitives import FULL_REACH
from shared.robot import MotionLimits, load_arm, motion_limits
from shared.robot.postures import rest

#: The reach the benchmark times: wrist target in the torso frame [m].
TARGET = (0.12, -0.13, 0.05)


class TimingCost(NamedTuple):
    """Results of the timing benchmark.

    Attributes:
        points: Path points timed.
        fastest: Time per call of our fastest timing [s].
        human: Time per call of our human-paced timing [s].
        peer: Time per call of toppra [s].
        fastest_duration: Duration of our fastest trajectory [s].
        human_duration: Duration of our human-paced trajectory [s].
        wanted_human_duration: The human default it was asked for [s].
        peer_duration: Duration of toppra's trajectory [s].
        peer_max_jerk_ratio: Largest |jerk| / jerk limit in toppra's samples.
    """

    points: int
    fastest: Timing
    human: Timing
    peer: Timing
    fastest_duration: float
    human_duration: float
    wanted_human_duration: float
    peer_duration: float
    peer_max_jerk_ratio: float

    @property
    def speedup(self) -> float:
        """Peer's mean cost over ours (fastest mode); > 1 means ours is cheaper."""
        return self.peer.mean / self.fastest.mean


def reach_joint_path(target: tuple[float, float, float] = TARGET) -> np.ndarray:
    """The right arm's joint path for a 1 s reach to ``target`` at 100 Hz, (101, 5)."""
    arm = load_arm("right")
    start = rest(arm.side)
    wrist = reach_path(arm, start, np.asarray(target), 1.0)
    return track_path(arm, wrist.positions, start, lambda k, kin: FULL_REACH).q


def toppra_trajectory(q: np.ndarray, limits: MotionLimits, rate: float = 100.0):  # type: ignore[no-untyped-def]
    """toppra's time-optimal trajectory along ``q`` (v, a limits), sampled.

    Returns (duration [s], positions (m, 5)).
    """
    import toppra
    import toppra.algorithm as algorithm
    import toppra.constraint as constraint

    toppra.setup_logging("WARNING")
    path = toppra.SplineInterpolator(np.linspace(0.0, 1.0, len(q)), q)
    speed = constraint.JointVelocityConstraint(
        np.column_stack((-limits.velocity, limits.velocity))
    )
    accel = constraint.JointAccelerationConstraint(
        np.column_stack((-limits.acceleration, limits.acceleration))
    )
    solver = algorithm.TOPPRA(
        [speed, accel], path, parametrizer="ParametrizeConstAccel"
    )
    trajectory = solver.compute_trajectory()
    times = np.arange(0.0, trajectory.duration, 1.0 / rate)
    return float(trajectory.duration), trajectory(np.append(times, trajectory.duration))


def run(q: np.ndarray | None = None, repeats: int = 50) -> TimingCost:
    """Time ours (fastest and human) and toppra on the same path ``repeats`` times."""
    arm = load_arm("right")
    limits = motion_limits(arm.limits)
    path = reach_joint_path() if q is None else np.asarray(q, dtype=float)
    wanted = reach_duration(arm, path[0], path[-1])
    fastest = time_path(path, limits)
    human = time_path(path, limits, duration=wanted)
    peer_duration, peer_q = toppra_trajectory(path, limits)
    return TimingCost(
        points=len(path),
        fastest=time_calls([lambda: time_path(path, limits)] * repeats),
        human=time_calls([lambda: time_path(path, limits, duration=wanted)] * repeats),
        peer=time_calls([lambda: toppra_trajectory(path, limits)] * repeats),
        fastest_duration=fastest.duration,
        human_duration=human.duration,
        wanted_human_duration=wanted,
        peer_duration=peer_duration,
        peer_max_jerk_ratio=_jerk_ratio(peer_q, limits, 0.01),
    )


def _jerk_ratio(q: np.ndarray, limits: MotionLimits, dt: float) -> float:
    """Largest |third difference| / dt^3 over the jerk limit (last step uneven)."""
    jerk = np.diff(q[:-1], 3, axis=0) / dt**3
    return float(np.max(np.abs(jerk) / limits.jerk)) if len(jerk) else 0.0


__all__ = ["TARGET", "TimingCost", "reach_joint_path", "run", "toppra_trajectory"]
