"""How the exported scripts move to the start: a minimum-jerk ``angleInterpolation``.

``play.py`` (``bridge.play_runner``) and the behavior's start box
(``bridge.start_box``) run without armplan, so they carry their own copy
of the bridge's approach (``bridge.approach``). They used to call
``angleInterpolationWithSpeed(names, start, 0.2)``, which moves each joint
in a straight line at a constant speed: its speed steps from 0 to 20 % of
the limit at once. Measured on the simulated NAO (``forward`` from rest,
RShoulderPitch 0.96 rad): at the 20 ms cycle a jerk of 2647 rad/s^3, 1.6
times the bridge's safety net (``net_limits``, 1654); at a 5 ms cycle an
acceleration of 259 rad/s^2 (3.1 times its 82.7) and a jerk of 31 times.

:func:`approach_source` is the Python (2 and 3) of ``LIMITS`` (each joint's
net speed, acceleration and jerk limits, from the robot description) and
``approach_keys(names, current, target, share)``: keys every
``1 / APPROACH_RATE`` s on the minimum-jerk blend from ``current`` to
``target`` [rad] (at rest, acceleration zero, at both ends), lasting the
shortest time (at least ``MIN_DURATION``) that keeps every joint's peak
speed, acceleration and jerk within ``share`` of its limits, as
``bridge.approach.approach_duration`` computes it; and
``check_arrived(names, commanded, target)``, which refuses to go on when
the move ended short of the start (within ``bridge.start_gap.START_TOLERANCE``
counts as there), as the bridge's ``bridge.arm_state.check_at_start`` does:
both scripts used to play the trajectory from wherever a move killed by
another client had left the arm. ``approach_keys`` refuses (RuntimeError,
nothing sent) a move whose keys bring the arm near NAO's body
(``bridge.script_body``).
"""

from __future__ import annotations

from bridge.approach import MIN_DURATION
from bridge.limits import FrameLimits
from bridge.minimum_jerk import PEAK_ACCELERATION, PEAK_JERK, PEAK_SPEED
from bridge.script_body import body_source
from bridge.start_gap import START_TOLERANCE
from shared.robot import Side

#: Keys per second of the move to the start [Hz]: ALMotion's 20 ms cycle.
APPROACH_RATE = 50.0

_SOURCE = '''

LIMITS = {limits}  # joint: (speed [rad/s], acceleration [rad/s^2], jerk [rad/s^3])


def approach_keys(names, current, target, share, others=()):
    """(keys, times) of a minimum-jerk move from ``current`` to ``target`` [rad].

    ``keys``: one list per joint [rad]; ``times``: one list per joint [s],
    every 1/{rate!r} s. Its length keeps each joint's peak speed,
    acceleration and jerk within ``share`` of LIMITS (at least {shortest!r} s).
    ``others``: parts besides the body the move keeps clear of (the other
    arm where the robot holds it, ``other_arm_parts``).
    """
    import math

    duration = {shortest!r}
    for name, here, there in zip(names, current, target):
        speed, acceleration, jerk = LIMITS[name]
        size = abs(there - here)
        duration = max(
            duration,
            {peak_speed!r} * size / (share * speed),
            math.sqrt({peak_acceleration!r} * size / (share * acceleration)),
            ({peak_jerk!r} * size / (share * jerk)) ** (1.0 / 3.0),
        )
    count = int(math.ceil(duration * {rate!r}))
    blend = [
        s ** 3 * (10.0 - 15.0 * s + 6.0 * s * s)
        for s in [float(k) / count for k in range(1, count + 1)]
    ]
    keys = [[a + (b - a) * f for f in blend] for a, b in zip(current, target)]
    times = [duration * k / count for k in range(1, count + 1)]
    check_clear(names, keys, [times] * len(keys), others=others)  # nothing sent
    return keys, [times] * len(keys)


def check_arrived(
    names,
    commanded,
    target,
    move="the move to the start",
    goal="the trajectory's start",
    outcome="nothing of the trajectory was sent",
):
    """Raise RuntimeError unless ``commanded`` [rad] is at ``target`` [rad].

    After the move to the start: a move ended early (another client's
    killAll or killTasksUsingResources, which NAOqi's blocking call may
    return from without an error; a posted move the robot refused) leaves
    the arm elsewhere, and the trajectory's first key would be a step from
    there that no check passed. Within {tolerance!r} rad (a hand's open
    fraction: as much) counts as there. ``move``, ``goal`` and
    ``outcome`` word the error for another move (the trajectory's end).
    """
    import math

    gaps = [abs(here - there) for here, there in zip(commanded, target)]
    gaps = [gap if gap == gap else float("inf") for gap in gaps]  # NaN: off
    worst = gaps.index(max(gaps))
    if gaps[worst] > {tolerance!r}:
        name = names[worst]
        if name.endswith("Hand"):
            off = "%.4f (open fraction)" % gaps[worst]
        else:
            off = "%.2f deg" % math.degrees(gaps[worst])
        raise RuntimeError(
            "%s ended with %s commanded at %.4f, %s from %s %.4f (stopped by "
            "another client, or refused by the robot); %s"
            % (move, name, commanded[worst], off, goal, target[worst], outcome)
        )
'''


def approach_source(side: Side | str) -> str:
    """``LIMITS`` and ``approach_keys`` for the arm and hand of ``side``.

    The limits are the bridge's safety net (``FrameLimits.for_arm``, the
    hand's ``with_hand``), from the robot description.
    """
    limits = FrameLimits.for_arm(side).with_hand(side)
    table = {
        name: (float(v), float(a), float(j))
        for name, v, a, j in zip(
            limits.names, limits.velocity, limits.acceleration, limits.jerk, strict=True
        )
    }
    return body_source(side) + _SOURCE.format(
        limits=repr(table),
        rate=APPROACH_RATE,
        shortest=MIN_DURATION,
        peak_speed=PEAK_SPEED,
        peak_acceleration=PEAK_ACCELERATION,
        peak_jerk=PEAK_JERK,
        tolerance=START_TOLERANCE,
    )


__all__ = ["APPROACH_RATE", "approach_source"]
