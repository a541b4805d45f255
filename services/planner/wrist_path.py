"""Human-like wrist paths on NAO: the hand swings about the shoulder.

People move the hand with a bell-shaped speed profile, well described by
minimum jerk (Flash and Hogan, 1985). NAO's wrist, moreover, lives in a thin
shell 0.114-0.162 m from the shoulder, where a straight segment between two
points often passes through the unreachable inside.

The path here therefore moves the wrist about the shoulder: its direction
from the shoulder turns along a great circle, and its distance from the
shoulder follows the elbow: the elbow's bend goes from its start value to
its end value with the same minimum-jerk progress, and the distance is the
one that bend gives the two segments (law of cosines, NAO's upper-arm and
forearm lengths). The hand's speed is then a bell, every point lies between
the two ends' distances from the shoulder (so in the shell when both ends
are), and the elbow, like the other joints, moves by a minimum-jerk law.

(The distance itself once changed with the minimum-jerk progress. Near a
straight arm a change of distance needs a large change of bend, so the
elbow then started with a jump; following the bend moved the grid reaches'
wrist paths nearer the demonstrations' and kept their human pace.)

(A variant in which the distance changed only after the first third of the
movement, the shoulder leading and the elbow joining later, was tried. On
NAO, whose ShoulderRoll turns the arm only 18 degrees inwards, a straight
arm cannot point at targets in front of the body, so the joints had to
catch up abruptly and the timing slowed the reaches to twice the human
duration. Fitted to the demonstrations, such a lead and lag moves the wrist
path nearer a person's, but NAO cannot keep the human pace along it within
its jerk limits: see docs/results.md.)
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from shared.robot.arm_model import ArmModel


class TimedPath(NamedTuple):
    """Wrist positions at times.

    Attributes:
        times: Sample times from the start [s], shape (n,).
        positions: Wrist positions in the torso frame [m], shape (n, 3).
    """

    times: np.ndarray
    positions: np.ndarray


def minimum_jerk(tau: np.ndarray) -> np.ndarray:
    """Minimum-jerk progress s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5, tau in [0, 1]."""
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)


def reach_path(
    arm: ArmModel,
    start_q: np.ndarray,
    goal: np.ndarray,
    duration: float,
    rate: float = 100.0,
) -> TimedPath:
    """A reach from where ``start_q`` puts the wrist to ``goal``, sampled at ``rate``.

    Args:
        arm: The arm (shoulder position, segment lengths).
        start_q: Posture at the start [rad], shape (5,).
        goal: Wrist target [m], shape (3,).
        duration: Movement time [s], > 0.
        rate: Samples per second [Hz].

    Returns:
        The path, from the start posture's wrist (t = 0) to ``goal``, sampled
        exactly every ``1 / rate`` s: ``ceil(duration * rate) + 1`` samples,
        the last at ``duration`` rounded up to a whole period.
    """
    points = arm.fk(np.asarray(start_q, dtype=float))
    shoulder, start = points.shoulder, points.wrist
    n = max(2, math.ceil(duration * rate - 1e-9) + 1)
    times = np.arange(n) / rate
    progress = minimum_jerk(times / times[-1])
    a, b = start - shoulder, np.asarray(goal, dtype=float) - shoulder
    ra, rb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    radius = bend_radius(ra, rb, progress, arm.upper_arm_length, arm.forearm_length)
    positions = shoulder + _slerp(a / ra, b / rb, progress) * radius[:, None]
    positions[0], positions[-1] = start, goal
    return TimedPath(times, positions)


def bend_radius(
    ra: float, rb: float, progress: np.ndarray, upper: float, fore: float
) -> np.ndarray:
    """Shoulder-to-wrist distance [m] while the elbow's bend moves with ``progress``.

    The bend that gives each end's distance (law of cosines with the
    segment lengths ``upper`` and ``fore`` [m]) is interpolated with
    ``progress`` (0..1, shape (n,)), and the distance it gives is corrected
    linearly so both ends are exactly ``ra`` and ``rb`` [m] (NAO's elbow
    offset makes the two-segment law a close approximation, not exact).

    Returns:
        Distances [m], shape (n,), from ``ra`` at progress 0 to ``rb`` at 1.
    """
    bend_a, bend_b = _bend(ra, upper, fore), _bend(rb, upper, fore)
    bend = bend_a + progress * (bend_b - bend_a)
    law = _distance(bend, upper, fore)
    miss_a = ra - float(_distance(np.array(bend_a), upper, fore))
    miss_b = rb - float(_distance(np.array(bend_b), upper, fore))
    return law + (1.0 - progress) * miss_a + progress * miss_b


def _bend(distance: float, upper: float, fore: float) -> float:
    """Elbow bend from straight [rad] at which the wrist is ``distance`` [m] away."""
    cos = (distance**2 - upper**2 - fore**2) / (2.0 * upper * fore)
    return math.acos(min(max(cos, -1.0), 1.0))


def _distance(bend: np.ndarray, upper: float, fore: float) -> np.ndarray:
    """Shoulder-to-wrist distance [m] at elbow bend ``bend`` [rad] (same shape)."""
    return np.sqrt(upper**2 + fore**2 + 2.0 * upper * fore * np.cos(bend))


def _slerp(ua: np.ndarray, ub: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Unit vectors from ``ua`` to ``ub`` on the great circle at fractions ``s``."""
    angle = math.acos(min(max(float(ua @ ub), -1.0), 1.0))
    s = s[:, None]
    if angle < 1e-6:
        out = ua + s * (ub - ua)
    else:
        out = (np.sin((1 - s) * angle) * ua + np.sin(s * angle) * ub) / math.sin(angle)
    return out / np.linalg.norm(out, axis=1, keepdims=True)
