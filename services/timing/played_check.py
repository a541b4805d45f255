"""A timed trajectory's played curve within the limits, and the limits to retime with.

The samples' divided differences (:func:`services.timing.check.check_limits`)
judge the samples; the robot plays the cubic Hermite curve through their
positions and velocities (:mod:`services.timing.played_curve`), whose
acceleration between samples can exceed the samples' where the path's jerk
changes inside a step: by up to ``8 J h / 27`` (5 % measured, at 25 Hz).
:func:`check_played` judges that curve at its exact maxima, and
:func:`retime_limits` gives the limits to time again with when it fails:
the limit less 1.5 times the excess, from the peak the timing reached (so
the retimed profile must change), never tighter than ``A - 8 J h / 27``,
which bounds the played acceleration by ``A`` whatever the samples' phase.
A plan that plays within its limits is returned as it was timed: no margin
slows plans that need none.

Positions are not judged: between samples near a joint's limit the curve
strays past it by a Hermite interpolation error (``J h^4`` scale: up to
3e-6 rad at 100 Hz and 1e-5 rad at 25 Hz measured), which retiming does
not remove; the bridge holds its curve in the ranges
(``bridge.interpolation.positions_at``).
"""

from __future__ import annotations

import numpy as np

from services.timing.check import RELATIVE_SLACK
from services.timing.finite_differences import rounding_noise
from services.timing.played_curve import CurveMaxima, curve_maxima, played_curve
from services.timing.trajectory import TimedTrajectory
from shared.errors import LimitViolationError
from shared.robot.motion_limits import MotionLimits

#: Times the played excess a retry takes off the limit, below the peak reached.
SAFETY = 1.5
#: The most a retry takes off a limit, as a factor of it.
DEEPEST = 0.8
#: Quantities judged, in the order their violations are named.
QUANTITIES = ("velocity", "acceleration", "jerk")


def played_maxima(result: TimedTrajectory) -> CurveMaxima:
    """Exact maxima of ``result``'s played curve per piece (m - 1, n)."""
    return curve_maxima(played_curve(result.times, result.positions, result.velocities))


def excess(result: TimedTrajectory, limits: MotionLimits) -> dict[str, np.ndarray]:
    """How far the played curve goes past each limit, per joint, shape (n,).

    Keys ``QUANTITIES``; [rad/s, rad/s^2, rad/s^3]; 0 where within (float
    round-off slack included, as in ``check_limits``).
    """
    if len(result.times) < 2:
        return {q: np.zeros(len(limits.names)) for q in QUANTITIES}
    peaks = played_maxima(result)._asdict()
    noise = rounding_noise(result.times, result.positions)
    out = {}
    for quantity in QUANTITIES:
        limit = getattr(limits, quantity)
        slack = limit * RELATIVE_SLACK + 2.0 * noise[quantity]
        over = peaks[quantity].max(axis=0) - limit - slack
        out[quantity] = np.maximum(over, 0.0)
    return out


def check_played(result: TimedTrajectory, limits: MotionLimits) -> None:
    """Raise if ``result``'s played curve exceeds a speed, acceleration or jerk limit.

    Raises:
        LimitViolationError: the worst violation (relative to its limit),
            naming the joint, the quantity, the value on the curve, the
            limit, and the sample the offending piece starts at.
    """
    over = excess(result, limits)
    ratios = {q: over[q] / getattr(limits, q) for q in QUANTITIES}
    quantity = max(QUANTITIES, key=lambda q: float(ratios[q].max()))
    if ratios[quantity].max() <= 0.0:
        return
    joint = int(np.argmax(ratios[quantity]))
    values = getattr(played_maxima(result), quantity)[:, joint]
    k = int(np.argmax(values))
    raise LimitViolationError(
        limits.names[joint],
        quantity,
        float(values[k]),
        float(getattr(limits, quantity)[joint]),
        k,
        float(result.times[k]),
        context=f"on the curve played between samples {k} and {k + 1}",
    )


def retime_limits(
    result: TimedTrajectory, limits: MotionLimits, tight: MotionLimits
) -> MotionLimits:
    """Limits to time again with: ``result``, timed under ``tight``, played over.

    Per joint and quantity that went over by ``e``: the smaller of the
    limit used and the peak the samples reached, less ``SAFETY e``; an
    acceleration never below ``A - 8 J h / 27`` (module doc) if that is
    positive, and no limit below ``DEEPEST`` times the one used.

    Args:
        result: The timing that failed, sampled every ``h`` [s].
        limits: The limits it must play within.
        tight: The limits it was timed with (``limits`` or tighter).
    """
    over = excess(result, limits)
    step = float(np.max(np.diff(result.times)))
    reached = {
        "velocity": np.abs(result.velocities).max(axis=0),
        "acceleration": np.abs(result.accelerations).max(axis=0),
        "jerk": np.abs(result.jerks).max(axis=0),
    }
    new = {}
    for quantity in QUANTITIES:
        used = getattr(tight, quantity)
        aimed = np.minimum(used, reached[quantity]) - SAFETY * over[quantity]
        if quantity == "acceleration":
            bound = limits.acceleration - 8.0 * tight.jerk * step / 27.0
            aimed = np.where(bound > 0.0, np.maximum(aimed, bound), aimed)
        aimed = np.clip(aimed, DEEPEST * used, used)
        new[quantity] = np.where(over[quantity] > 0.0, aimed, used)
        new[quantity].setflags(write=False)
    return tight._replace(**new)


__all__ = ["check_played", "excess", "played_maxima", "retime_limits"]
