"""A trajectory's velocities checked against its positions, before any frame.

The bridge's curve between samples is the cubic Hermite curve through the
samples' positions *and velocities* (``bridge.interpolation``), and every
later check (limits, frame rate, behavior) is made on that curve: wrong
velocities make a wrong curve that passes them all. Times written in
milliseconds with the speeds left in rad/s swung RShoulderPitch across its
range and pinned RShoulderRoll at its limit, 144 degrees from the plan
slowed 1000 times; a plan slowed 20 times by scaling its times alone was
played 2.7 degrees off. So the velocities are compared with the positions
first.

The positions' own curve is the clamped cubic spline through them (C2, at
rest at both ends, as the robot is before and after every trajectory it
plays): on each stretch it is the Hermite curve through the positions with
the spline's slopes ``m_k``. The bridge's curve differs from it on stretch
``k`` (step ``h``, ``s`` in 0..1, ``E = v - m``) by exactly

    gap(s) = h (E_k s (1 - s)^2 - E_(k+1) s^2 (1 - s)),

which is at most ``h max(|E_k|, |E_(k+1)|) / 4``. The chord (the line
between the stretch's samples: slopes both its mean speed) is the other
curve the positions alone make: on a stretch far longer than the ones
before it (a hold written as one stretch, at rest, its samples minutes
apart) the spline rings, its slope there set by the samples before (3.2
degrees over a reach held to 80 000 s), while the trajectory's curve is as
still as the chord. A stretch whose curve strays from both by more than the
joint's tolerance (``bridge.fidelity.follow_tolerance``: one degree, the
tracking the bridge holds frames to; a joint's 25 fps chord gap if larger,
2.8 degrees for WristYaw) is refused.

Why every correct trajectory within the bridge's jerk limits passes when
sampled finely: let ``q`` be at rest at both ends with ``|q'''| <= J`` (a
jerk that may jump, as Ruckig's does), sampled every ``h`` with its own
velocities ``v_k = q'(t_k)``. The spline's slopes solve ``m_(k-1) + 4 m_k +
m_(k+1) = 3 (q_(k+1) - q_(k-1)) / h`` with ``m_0 = m_n = 0``; the true
slopes leave the residual

    r_k = 3 (q_(k+1) - q_(k-1)) / h - (v_(k-1) + 4 v_k + v_(k+1))
        = integral over 0..h of K(u) (q'''(t_k + u) + q'''(t_k - u)) du,
    K(u) = (h - u) (h - 3 u) / (2 h),

(Taylor with integral remainders), where ``K`` integrates to 0 and its
absolute value to ``4 h^2 / 27``: ``|r_k| <= 8 J h^2 / 27``. The errors
``E`` solve the same rows with ``r`` on the right and ``E_0 = E_n = 0``;
a row's diagonal beats its neighbours by 2, so ``|E_k| <= 4 J h^2 / 27``
and the gap is at most ``J h^3 / 27``. With the bridge's jerk limits
(1439..4925 rad/s^3) that is within a degree up to ``h`` = 0.066 s: any
such trajectory sampled at 16 Hz or more passes, whatever its motion
(:func:`fine_rate`). The planner samples at 100 Hz by default (bound
0.0035 degree; about 0.0001 measured); a ``--wrist-path`` carries exactly
the spline's slopes (gap 0 at any spacing), and the hand's planned speeds
are exact. A plan sampled coarser than 16 Hz passes if its motion between
samples is gentle enough (planned reaches measured up to 0.2 degree at 10
Hz, 0.9 at 5 Hz, 7.8 at 2 Hz): below that, samples too far apart to show
the movement are refused as wrong velocities are, and the refusal says
both.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from bridge.checks import check_joints
from bridge.fidelity import follow_tolerance, gap_shown
from bridge.hand import with_hand
from bridge.limits import FrameLimits
from bridge.units import unit
from shared.errors import TrajectoryRefusedError, fixed
from shared.messages import Trajectory


def check_velocities(trajectory: Trajectory, limits: FrameLimits) -> None:
    """Refuse ``trajectory`` if its velocities disagree with its positions.

    The hand's speeds are checked when the trajectory carries them
    (``Trajectory.hand_velocities``); without them the bridge makes them
    from the hand's positions, and there is nothing to disagree.

    Args:
        trajectory: The trajectory [s, rad, rad/s], its hand a channel.
        limits: The arm's joints' limits (the hand's are added with it).

    Raises:
        InvalidInputError: its joints are not the limits'.
        TrajectoryRefusedError: quantity ``"velocities"``, naming the joint
            and the sample whose velocity strays most (value: the gap the
            velocities make [rad; open fraction for a hand], limit: the
            tolerance).
    """
    if trajectory.hand is not None and trajectory.hand_velocities is None:
        trajectory = trajectory.model_copy(
            update={"hand": None, "hand_velocities": None, "hand_accelerations": None}
        )
    trajectory, limits = with_hand(trajectory, limits)
    check_joints(trajectory.joint_names, limits)
    t = np.asarray(trajectory.times, dtype=float)
    if len(t) < 2:
        return
    q = np.asarray(trajectory.positions, dtype=float)
    v = np.asarray(trajectory.velocities, dtype=float)
    slopes = positions_slopes(t, q)
    gap = stretch_gaps(v, slopes, q, t)
    tolerance = follow_tolerance(limits)
    ratio = gap / tolerance
    k, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
    if ratio[k, j] <= 1.0:
        return
    worse = abs(v[k + 1, j] - slopes[k + 1, j]) > abs(v[k, j] - slopes[k, j])
    raise _refusal(limits, (int(k), int(k + worse)), int(j), t, v, slopes, gap[k, j])


def positions_slopes(times: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """Slopes of the positions' own curve at the samples [rad/s], shape (n, j).

    The clamped cubic spline through ``positions`` [rad] (n, j) at
    ``times`` [s] (n,), n >= 2: C2, at rest (slope 0) at both ends.
    """
    spline = CubicSpline(times, positions, bc_type="clamped", axis=0)
    return np.asarray(spline(times, 1))


def stretch_gaps(
    velocities: np.ndarray, slopes: np.ndarray, positions: np.ndarray, times: np.ndarray
) -> np.ndarray:
    """How far the curve through ``velocities`` strays from the positions' [rad].

    On each stretch, the smaller of its largest gaps from the positions'
    own curve (the Hermite curve with ``slopes``) and from the chord.

    Args:
        velocities: The trajectory's velocities [rad/s], shape (n, j).
        slopes: The positions' curve's slopes (:func:`positions_slopes`).
        positions: The positions [rad], shape (n, j).
        times: Their times [s], shape (n,), n >= 2.

    Returns:
        Gaps [rad], shape (n - 1, j): stretch ``k`` from sample ``k`` to
        ``k + 1``.
    """
    steps = np.diff(times)[:, None]
    chord = np.diff(positions, axis=0) / steps
    error = velocities - slopes
    return np.minimum(
        hermite_gaps(error[:-1], error[1:], steps),
        hermite_gaps(velocities[:-1] - chord, velocities[1:] - chord, steps),
    )


def hermite_gaps(e0: np.ndarray, e1: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Largest gap between two Hermite curves on each stretch [rad], (m, j).

    The curves share the stretch's end positions; their slopes differ by
    ``e0`` at its start and ``e1`` at its end [rad/s], each shape (m, j),
    over ``steps`` [s] (m, 1). The gap is ``h (e0 s (1 - s)^2 - e1 s^2 (1 -
    s))``, ``s`` in 0..1; its extremes lie where its derivative ``3 (e0 +
    e1) s^2 - (4 e0 + 2 e1) s + e0`` is 0, whose discriminant ``4 (e0^2 + e0
    e1 + e1^2)`` is never negative. The roots are taken in the form that
    loses no digits, of the differences scaled to at most 1 (no overflow for
    a velocity of 1e200).
    """
    scale = np.maximum(np.abs(e0), np.abs(e1))
    e0, e1 = (e / np.where(scale > 0.0, scale, 1.0) for e in (e0, e1))
    b = 4.0 * e0 + 2.0 * e1
    root = 2.0 * np.sqrt(e0**2 + e0 * e1 + e1**2)
    big = b + np.where(b < 0.0, -root, root)
    with np.errstate(divide="ignore", invalid="ignore"):
        roots = (big / (6.0 * (e0 + e1)), 2.0 * e0 / big)
    gap = np.zeros_like(e0)
    for s in roots:
        s = np.clip(np.nan_to_num(s, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
        gap = np.maximum(gap, np.abs(e0 * s * (1 - s) ** 2 - e1 * s**2 * (1 - s)))
    return steps * (scale * gap)


def fine_rate(jerk: float, tolerance: float) -> float:
    """Sample rate [Hz] from which any trajectory within ``jerk`` passes.

    Its gap is at most ``J h^3 / 27`` (module doc), within ``tolerance``
    [rad] for steps up to ``(27 tolerance / J)^(1/3)``.

    Args:
        jerk: The joint's jerk limit [rad/s^3].
        tolerance: Its largest allowed gap [rad].
    """
    return float((jerk / (27.0 * tolerance)) ** (1.0 / 3.0))


def _refusal(
    limits: FrameLimits,
    samples: tuple[int, int],
    j: int,
    t: np.ndarray,
    velocities: np.ndarray,
    slopes: np.ndarray,
    gap: float,
) -> TrajectoryRefusedError:
    """The refusal of joint ``j``'s stretch ``samples`` (start, the worse end)."""
    (k, worse), name = samples, limits.names[j]
    tolerance = follow_tolerance(limits)[j]
    rate = math.ceil(fine_rate(limits.jerk[j], tolerance))
    speed, at = unit(name, 1), t[worse] - t[0]
    coarse = (
        "If they are right, the samples are too far apart to show the movement: "
        f"sample it at {rate} Hz or more, where any trajectory within the limits "
        "passes"
        if t[k + 1] - t[k] > 1.0 / rate
        else f"Sampled at {rate} Hz or more, a trajectory within the limits passes "
        "only if they agree"
    )
    return TrajectoryRefusedError(
        name,
        "velocities",
        gap,
        tolerance,
        frame=worse,
        time=at,
        detail=(
            f"velocity {fixed(velocities[worse, j], 3)}{speed} at sample {worse} "
            f"(t = {at:.3f} s) disagrees with the positions (their curve: "
            f"{fixed(slopes[worse, j], 3)}{speed} there): through these "
            f"velocities the curve between samples {k} and {k + 1} strays at least "
            f"{gap_shown(name, gap, '.1f')} both from the positions' own and from "
            f"the line between them (at most {gap_shown(name, tolerance, '.3g')}); "
            "are the velocities in other units, or the times scaled without "
            f"them? {coarse}"
        ),
    )
