"""One-DoF jerk-limited motion of the path parameter, by Ruckig.

Ruckig (community edition) computes the time-optimal rest-to-rest profile of
u from 0 to the path's length under (V, A, J), locally, with no waypoints
(never ``intermediate_positions``, which the community edition sends to a
remote service). The profile is seven phases of constant jerk;
:meth:`ScalarProfile.sample` evaluates it at many times at once.

Under (V / r, A / r^2, J / r^3) the time-optimal profile is the same one run
r times slower (:func:`scaled`): that is how a profile is stretched to fit the
joints' limits, or to end on a whole number of sample periods.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from ruckig import InputParameter, Result, Ruckig, Trajectory

from services.timing.parameter_limits import ParameterLimits
from shared.errors import TimingError


class ProfileSample(NamedTuple):
    """u and its derivatives at sample times; each shape (m,).

    Attributes:
        position: u.
        velocity: u_dot [1/s].
        acceleration: u_ddot [1/s^2].
        jerk: u_dddot [1/s^3].
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray


class ScalarProfile(NamedTuple):
    """A piecewise constant-jerk motion of one scalar.

    Attributes:
        starts: Start time of each phase [s], shape (7,).
        jerk: Jerk of each phase, shape (7,).
        acceleration: Acceleration at each phase start, shape (7,).
        velocity: Velocity at each phase start, shape (7,).
        position: Position at each phase start, shape (7,).
        duration: Total time [s].
        length: Final position.
    """

    starts: np.ndarray
    jerk: np.ndarray
    acceleration: np.ndarray
    velocity: np.ndarray
    position: np.ndarray
    duration: float
    length: float

    def sample(self, times: np.ndarray) -> ProfileSample:
        """The motion at ``times`` [s] (m,), clamped into [0, duration]."""
        t = np.clip(times, 0.0, self.duration)
        phase = np.searchsorted(self.starts, t, side="right") - 1
        dt = t - self.starts[phase]
        j, a = self.jerk[phase], self.acceleration[phase]
        v, p = self.velocity[phase], self.position[phase]
        position = p + dt * (v + dt * (a / 2.0 + dt * j / 6.0))
        return ProfileSample(
            np.clip(position, 0.0, self.length),
            v + dt * (a + dt * j / 2.0),
            a + dt * j,
            j,
        )


def plan_rest_to_rest(length: float, limits: ParameterLimits) -> ScalarProfile:
    """Ruckig's time-optimal profile from u = 0 to ``length``, at rest at both ends.

    Args:
        length: Distance to travel (> 0).
        limits: Bounds on |u_dot|, |u_ddot|, |u_dddot|.

    Raises:
        TimingError: Ruckig found no profile.
    """
    otg = Ruckig(1)
    inp = InputParameter(1)
    inp.current_position = [0.0]
    inp.target_position = [length]
    inp.max_velocity = [limits.velocity]
    inp.max_acceleration = [limits.acceleration]
    inp.max_jerk = [limits.jerk]
    trajectory = Trajectory(1)
    result = otg.calculate(inp, trajectory)
    if result not in (Result.Working, Result.Finished):
        raise TimingError(
            f"Ruckig found no profile over {length:.6g} with limits "
            f"{tuple(limits)}: {result}",
            length=length,
            limits=list(limits),
        )
    return _profile(trajectory, length)


def scaled(limits: ParameterLimits, factor: float) -> ParameterLimits:
    """Limits whose time-optimal profile is the original one ``factor`` times slower."""
    return ParameterLimits(
        limits.velocity / factor,
        limits.acceleration / factor**2,
        limits.jerk / factor**3,
    )


def _profile(trajectory: Trajectory, length: float) -> ScalarProfile:
    """The phases of Ruckig's trajectory as arrays."""
    profile = trajectory.profiles[0][0]
    if profile.brake.duration > 0.0 or profile.accel.duration > 0.0:
        raise TimingError(
            "Ruckig needed a braking pre-trajectory from rest, which cannot happen",
            length=length,
        )
    starts, elapsed = [0.0], 0.0
    for phase in profile.t[:-1]:  # a running sum, as np.cumsum adds
        elapsed += phase
        starts.append(elapsed)
    return ScalarProfile(
        starts=np.array(starts),
        jerk=np.array(profile.j),
        acceleration=np.array(profile.a[:-1]),
        velocity=np.array(profile.v[:-1]),
        position=np.array(profile.p[:-1]),
        duration=float(trajectory.duration),
        length=float(length),
    )


__all__ = ["ProfileSample", "ScalarProfile", "plan_rest_to_rest", "scaled"]
