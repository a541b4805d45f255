"""Speed, acceleration and jerk limits of one arm's joints, for timing and checks.

Speed limits and position ranges come from the robot description (the URDF,
through :class:`~shared.robot.limits.JointLimits`); they are never repeated
here. Acceleration and jerk limits are not in a URDF: by default each joint
may reach its full speed from rest in ``ACCELERATION_TIME`` and build its full
acceleration in ``JERK_TIME``, so

    acceleration = velocity / ACCELERATION_TIME   [rad/s^2]
    jerk = acceleration / JERK_TIME               [rad/s^3]

Why a NAO can follow these (defaults: 0.25 s and 0.05 s):

- Torque: at the default accelerations the torque the arm's own links need
  (joint-space inertia from the URDF times the accelerations, plus gravity)
  stays below 75 % of each joint's effort limit in every posture, which leaves
  room for the motors' rotor inertia and friction that the URDF does not hold
  (``tests/test_motion_limits.py`` checks it over random postures).
- Control: ALMotion runs a 20 ms cycle; a 50 ms jerk ramp spans 2.5 cycles, so
  the position loop sees a smooth reference instead of a step in acceleration.
- Human reaches fit inside: a minimum-jerk-like 0.55 s reach (Table 4's
  shortest) moving a shoulder joint by 1.5 rad needs about 26 rad/s^2 and
  about 420 rad/s^3, below the defaults' 33 rad/s^2 and 660 rad/s^3.

Either default can be replaced, per joint or for all joints, with
:func:`motion_limits` (a request's ``TimingLimits``: :func:`asked_limits`),
up to the bridge's safety net (:func:`net_limits`): speed from rest in
``NET_ACCELERATION_TIME``, acceleration built in ``JERK_TIME``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from shared.errors import InvalidInputError
from shared.robot.limits import JointLimits

#: Time from rest to full speed at the default acceleration limit [s].
ACCELERATION_TIME = 0.25
#: Time from zero to full acceleration at the default jerk limit [s].
JERK_TIME = 0.05
#: Time from rest to full speed at the bridge's safety net [s]: NAO's arm
#: motors reach their no-load speed in about a tenth of a second.
NET_ACCELERATION_TIME = 0.1
#: How many times below its default a request's acceleration limit may be
#: (and its jerk limit, ``SLOWEST_JERK``): at both floors a joint crosses
#: its whole range in about 10 s. Slower is a creep, and limits with no floor
#: (1e-9 rad/s^2) made trajectories of millions of samples, gigabytes of
#: memory, before the sample cap could refuse them.
SLOWEST_ACCELERATION = 100.0
#: The same for the jerk limit.
SLOWEST_JERK = 1000.0


class MotionLimits(NamedTuple):
    """Position, speed, acceleration and jerk limits of a set of joints.

    Attributes:
        names: NAO joint names, shape (n,).
        lower: Lower position limits [rad], shape (n,).
        upper: Upper position limits [rad], shape (n,).
        velocity: Speed limits [rad/s], shape (n,).
        acceleration: Acceleration limits [rad/s^2], shape (n,).
        jerk: Jerk limits [rad/s^3], shape (n,).
    """

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray

    def scaled(self, factor: float) -> MotionLimits:
        """These limits with speed, acceleration and jerk times ``factor`` (0, 1]."""
        if not 0.0 < factor <= 1.0:
            raise InvalidInputError(
                f"limit scale factor {factor} is outside (0, 1]", field="factor"
            )
        return self._replace(
            velocity=_frozen(self.velocity * factor),
            acceleration=_frozen(self.acceleration * factor),
            jerk=_frozen(self.jerk * factor),
        )


def motion_limits(
    joints: JointLimits,
    *,
    acceleration: npt.ArrayLike | None = None,
    jerk: npt.ArrayLike | None = None,
) -> MotionLimits:
    """The motion limits of ``joints``, defaults where a value is not given.

    Args:
        joints: Position and speed limits from the robot description
            (``ArmModel.limits``).
        acceleration: Acceleration limits [rad/s^2], a scalar for every joint
            or shape (n,); default ``velocity / ACCELERATION_TIME``.
        jerk: Jerk limits [rad/s^3], a scalar or shape (n,); default
            ``acceleration / JERK_TIME``.

    Raises:
        InvalidInputError: a limit is not a positive finite number, or has
            the wrong shape.
    """
    velocity = np.asarray(joints.velocity, dtype=float)
    acc = _per_joint(
        "acceleration", velocity / ACCELERATION_TIME, acceleration, joints.names
    )
    jrk = _per_joint("jerk", acc / JERK_TIME, jerk, joints.names)
    return MotionLimits(
        names=tuple(joints.names),
        lower=_frozen(joints.lower),
        upper=_frozen(joints.upper),
        velocity=_frozen(velocity),
        acceleration=acc,
        jerk=jrk,
    )


def _per_joint(
    name: str,
    default: np.ndarray,
    given: npt.ArrayLike | None,
    names: tuple[str, ...],
) -> np.ndarray:
    """``given`` broadcast to one value per joint (``default`` if None), checked."""
    if given is None:
        return _frozen(default)
    try:
        values = np.broadcast_to(np.asarray(given, dtype=float), default.shape)
    except ValueError:
        raise InvalidInputError(
            f"{name} limits need one value or {len(names)} values, got "
            f"shape {np.shape(given)}",
            field=name,
        ) from None
    bad = ~(np.isfinite(values) & (values > 0.0))
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InvalidInputError(
            f"{name} limit of {names[k]} is {values[k]}: it must be a positive "
            "finite number",
            field=name,
            joint=names[k],
        )
    return _frozen(values)


def _frozen(values: npt.ArrayLike) -> np.ndarray:
    """A read-only float copy of ``values``."""
    array = np.array(values, dtype=float)
    array.setflags(write=False)
    return array


def net_limits(joints: JointLimits) -> MotionLimits:
    """The bridge's safety net [rad/s^2, rad/s^3]: the highest limits allowed.

    Acceleration: speed limit / ``NET_ACCELERATION_TIME``; jerk: that
    / ``JERK_TIME`` (2.5 times the defaults of both).
    """
    velocity = np.asarray(joints.velocity, dtype=float)
    return motion_limits(joints, acceleration=velocity / NET_ACCELERATION_TIME)


def asked_limits(
    joints: JointLimits,
    acceleration: npt.ArrayLike | None = None,
    jerk: npt.ArrayLike | None = None,
) -> MotionLimits:
    """:func:`motion_limits` with a request's limits, checked against the net.

    Args:
        joints: Position and speed limits from the robot description.
        acceleration: [rad/s^2], a scalar or shape (n,), or None (default).
        jerk: [rad/s^3], a scalar or shape (n,), or None (default).

    Raises:
        InvalidInputError: a limit that is not a positive finite number,
            below its floor (``SLOWEST_ACCELERATION``, ``SLOWEST_JERK``) or
            above the net (:func:`net_limits`), naming the joint and the bound.
    """
    limits = motion_limits(joints, acceleration=acceleration, jerk=jerk)
    net, default = net_limits(joints), motion_limits(joints)
    floors = {"acceleration": SLOWEST_ACCELERATION, "jerk": SLOWEST_JERK}
    for name, unit in (("acceleration", "rad/s^2"), ("jerk", "rad/s^3")):
        asked, most = getattr(limits, name), getattr(net, name)
        least = getattr(default, name) / floors[name]
        under = asked < least * (1.0 - 1e-12)
        if np.any(under):
            k = int(np.argmax(under))
            raise InvalidInputError(
                f"{name} limit of {joints.names[k]} is {asked[k]:g} {unit}, below "
                f"the {least[k]:.3g} {unit} allowed (1/{floors[name]:g} of the "
                "default): slower is a creep, a joint taking over 10 s across "
                "its range",
                field=name,
                joint=joints.names[k],
            )
        over = asked > most * (1.0 + 1e-12)
        if np.any(over):
            k = int(np.argmax(over))
            raise InvalidInputError(
                f"{name} limit of {joints.names[k]} is {asked[k]:g} {unit}, above "
                f"the {most[k]:g} {unit} the robot bridge allows (its safety net): "
                "the bridge would refuse the trajectory",
                field=name,
                joint=joints.names[k],
            )
    return limits


__all__ = [
    "ACCELERATION_TIME",
    "JERK_TIME",
    "NET_ACCELERATION_TIME",
    "SLOWEST_ACCELERATION",
    "SLOWEST_JERK",
    "MotionLimits",
    "asked_limits",
    "motion_limits",
    "net_limits",
]
