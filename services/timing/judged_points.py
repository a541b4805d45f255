"""Where the stretch judges the joints' derivatives along a timed spline.

The joints' jerk q''' = s''' u'^3 + 3 s'' u' u'' + s' u''' (s the spline
q(u), u(t) Ruckig's profile) is smooth between the spline's knots and the
profile's phase boundaries, and jumps at both: the spline is C2 (its third
derivative steps at each knot) and the profile's jerk is piecewise constant.
An even grid of times misses those steps whenever its points straddle one,
and a knot's step can be the largest jerk of the path: a left-arm task
(``tests/test_timing_knot_jerk.py``) had its jerk 1.76 times the limit just
past a knot while the grid saw 1.60, and its samples, 10 ms apart, changed
acceleration 1.19 times faster than the limit allows. Of the sections of
100 random tasks a fifth went over the limit between grid points (up to 5.5
times it, mostly for less than a sample period).

So besides the even grid the stretch is judged on each side of every phase
boundary and of every knot, and at ``PER_PIECE`` evenly spaced points
inside every piece (a piece the profile crosses between two grid times).
A point given in u is placed in time by interpolating the grid's u(t) and
one Newton step on the profile; the spline is evaluated at the exact u.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from services.timing.path_spline import PathSpline
from services.timing.scalar_profile import ScalarProfile

#: Evaluation points inside every spline piece, besides its two knots.
PER_PIECE = 1


class Judged(NamedTuple):
    """The path's derivatives and the profile's at the judged points; (m, n) / (m,).

    Attributes:
        first, second, third: dq/du, d2q/du2, d3q/du3, shape (m, n).
        velocity, acceleration, jerk: u_dot, u_ddot, u_dddot, shape (m,).
    """

    first: np.ndarray
    second: np.ndarray
    third: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray


def judged(spline: PathSpline, profile: ScalarProfile, count: int) -> Judged:
    """Derivatives at ``count`` even times, phase sides, knot sides and piece points."""
    grid = np.linspace(0.0, profile.duration, count)
    boundaries = profile.starts[1:][profile.starts[1:] < profile.duration]
    times = np.concatenate((grid, boundaries, np.nextafter(boundaries, -np.inf)))
    u = profile.sample(times)
    values = _piece_points(spline)
    at = profile.sample(_times_of(profile, values, grid, u.position[:count]))
    s = spline.evaluate(np.concatenate((u.position, values)))
    return Judged(
        s.first,
        s.second,
        s.third,
        np.concatenate((u.velocity, at.velocity)),
        np.concatenate((u.acceleration, at.acceleration)),
        np.concatenate((u.jerk, at.jerk)),
    )


def _piece_points(spline: PathSpline) -> np.ndarray:
    """u at each knot's two sides and inside every piece, shape (m,).

    ``spline.evaluate`` places a knot in the piece it starts; the float just
    below it lies in the piece that ends there.
    """
    knots = spline.knots[1:-1]
    inside = (
        spline.knots[:-1, None]
        + spline.widths[:, None] * np.arange(1, PER_PIECE + 1) / (PER_PIECE + 1)
    ).ravel()
    return np.concatenate((knots, np.nextafter(knots, -np.inf), inside))


def _times_of(
    profile: ScalarProfile, values: np.ndarray, grid: np.ndarray, at_grid: np.ndarray
) -> np.ndarray:
    """Times [s] at which u reaches ``values`` (m,), shape (m,).

    Linear in the grid's u(t) (non-decreasing), then one Newton step on the
    profile, kept within the two grid times around the value.
    """
    right = np.clip(np.searchsorted(at_grid, values, side="left"), 1, len(grid) - 1)
    low, high = grid[right - 1], grid[right]
    rise = at_grid[right] - at_grid[right - 1]
    share = np.divide(
        values - at_grid[right - 1], rise, out=np.zeros_like(values), where=rise > 0
    )
    t = low + np.clip(share, 0.0, 1.0) * (high - low)
    u = profile.sample(t)
    step = np.divide(
        u.position - values, u.velocity, out=np.zeros_like(t), where=u.velocity > 0
    )
    return np.clip(t - step, low, high)


__all__ = ["PER_PIECE", "Judged", "judged"]
