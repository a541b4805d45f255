"""The motion of the path parameter: a Ruckig profile that just fits the limits.

Two shapes of rest-to-rest profile for u:

- the human bell of a given duration (:mod:`services.timing.human_pace`); it
  keeps its duration if the joints allow it, and is slowed down just enough
  if not;
- the fastest: the shorter of the guaranteed limits' profile
  (:func:`~services.timing.parameter_limits.parameter_limits`) and the bell,
  each sped up (or slowed down) until it just fits, so it is never slower
  than the human pace.

"Just fits" is :func:`~services.timing.profile_scale.required_scale`, applied
as a time scale (:func:`~services.timing.scalar_profile.scaled`) together with
the small stretch that makes the profile end on a whole number of sample
periods. Time-scaling maps the check's grid and margins onto themselves, so
one check before scaling is exact for the scaled profile.
"""

from __future__ import annotations

import numpy as np

from services.timing.human_pace import bell_limits
from services.timing.parameter_limits import ParameterLimits, parameter_limits
from services.timing.path_spline import PathSpline
from services.timing.profile_scale import required_scale
from services.timing.scalar_profile import ScalarProfile, plan_rest_to_rest, scaled
from shared.robot.motion_limits import MotionLimits


def fit_profile(
    spline: PathSpline,
    limits: MotionLimits,
    duration: float | None,
    period: float,
) -> ScalarProfile:
    """u(t) along ``spline``: the bell of ``duration`` [s], or the fastest (None).

    The result's duration is a whole number of ``period`` [s].
    """
    if duration is not None:
        bell = bell_limits(spline.length, duration)
        return just_fitting(spline, bell, limits, period, slower_only=True)
    shapes = (
        parameter_limits(spline.bounds(), limits, spline.length),
        bell_limits(spline.length, 1.0),
    )
    profiles = [just_fitting(spline, shape, limits, period) for shape in shapes]
    return min(profiles, key=lambda profile: profile.duration)


def just_fitting(
    spline: PathSpline,
    u_limits: ParameterLimits,
    limits: MotionLimits,
    period: float,
    *,
    slower_only: bool = False,
) -> ScalarProfile:
    """The time-optimal profile under ``u_limits``, run just slow enough.

    Args:
        spline: The path q(u).
        u_limits: Limits giving the profile's shape.
        limits: The joints' limits it must fit.
        period: Sample period [s]; the duration becomes a multiple of it.
        slower_only: Never run faster than ``u_limits`` allow (the bell).
    """
    profile = plan_rest_to_rest(spline.length, u_limits)
    factor = required_scale(spline, profile, u_limits, limits, period)
    if slower_only:
        factor = max(factor, 1.0)
    periods = np.ceil(factor * profile.duration / period - 1e-9)
    total = periods * period / profile.duration
    return plan_rest_to_rest(spline.length, scaled(u_limits, total))


__all__ = ["fit_profile", "just_fitting"]
