"""How the exported scripts stiffen the arm: awake, and a limp arm held where it hangs.

``play.py`` (``bridge.python_export``) and the behavior's start box
(``bridge.start_box``) run on a robot without armplan, so they carry
their own copy of what the bridge does before it stiffens an arm
(``bridge.awake``, ``bridge.limp_arm``). They used to call
``setStiffnesses(names, 1.0)`` at once: an arm made limp (the fall
manager, another client's ``setStiffnesses("RArm", 0)``) had sagged from
its command, and stiffened in one step it snapped back at its motors' top
speed (RShoulderPitch 0.3 rad at 97 % of its speed limit within 37 ms on
the simulated NAO), on a robot the bridge would have refused as not awake.

:data:`STIFFEN_SOURCE` is the Python (2 and 3) of one function,
``stiffen_where_it_is(motion, names)``: it raises ``RuntimeError`` (nothing
sent) if ``ALMotion.robotIsWakeUp()`` is false, or if the arm does not
hold still, free of every motion task, within ``STILL_WAIT``
(``wait_until_free``, as the bridge's ``bridge.at_rest``: the scripts
used to cut another client's movement off mid-way, stopping the arm dead,
on the simulated NAO, or start from where a NAO would not have it); reads
each joint's
stiffness, and for the limp ones (below ``LIMP``, as the bridge's
``arm_state.LIMP``) reads their sensors every ``SETTLE_GAP`` until two
readings agree within ``SETTLED`` (an arm let go falls for about 0.3 s;
still moving after ``SETTLE_WAIT``: ``RuntimeError``, nothing sent), and
moves their command there (``angleInterpolation`` at ``HOLD_SPEED`` of the
robot's speed limits, ``getLimits``, ``RuntimeError`` if one is not
positive; limp motors do not follow); then
ramps every joint to stiffness 1 over ``STIFFEN_TIME`` (NAOqi's
``stiffnessInterpolation``). The script then moves slowly to the start as
before.
"""

from __future__ import annotations

from bridge.arm_state import LIMP
from bridge.at_rest import READ_GAP, STILL, STILL_WAIT
from bridge.limp_arm import HOLD_SHORTEST, HOLD_SPEED, SETTLE_GAP, SETTLE_WAIT, SETTLED

#: Length of the stiffness ramp [s] (the bridge's ``NaoqiClient.stiffen``).
STIFFEN_TIME = 0.2

STIFFEN_SOURCE = f'''

def stiffen_where_it_is(motion, names):
    """Stiffen ``names`` where they are: a limp joint's command first goes there.

    Raises RuntimeError, nothing sent, if the robot is not awake, a limp
    joint is still moving (falling) after {SETTLE_WAIT} s, or the robot
    gives a limp joint no speed limit.
    """
    import time

    if not motion.robotIsWakeUp():
        raise RuntimeError(
            "the robot is not awake (robotIsWakeUp() is false); nothing was "
            "sent: wake it up (ALMotion.wakeUp) and run this again"
        )
    wait_until_free(motion, names)
    stiffness = motion.getStiffnesses(names)
    limp = [n for n, s in zip(names, stiffness) if not s >= {LIMP!r}]
    if limp:
        deadline = time.time() + {SETTLE_WAIT!r}
        before = motion.getAngles(limp, True)
        while True:
            time.sleep({SETTLE_GAP!r})
            hangs = motion.getAngles(limp, True)
            if max(abs(a - b) for a, b in zip(hangs, before)) <= {SETTLED!r}:
                break
            if time.time() >= deadline:
                raise RuntimeError(
                    "the arm is still moving (limp, falling?); nothing was sent"
                )
            before = hangs
        commanded = motion.getAngles(limp, False)
        speeds = [{HOLD_SPEED!r} * motion.getLimits(n)[0][2] for n in limp]
        for name, speed in zip(limp, speeds):
            if not speed > 0:
                raise RuntimeError(
                    "the robot gives %s no speed limit (getLimits: %r rad/s); "
                    "nothing was sent" % (name, speed / {HOLD_SPEED!r})
                )
        duration = max(
            [{HOLD_SHORTEST!r}]
            + [abs(a - c) / v for a, c, v in zip(hangs, commanded, speeds)]
        )
        motion.angleInterpolation(
            limp, [[a] for a in hangs], [[duration]] * len(limp), True
        )
    motion.stiffnessInterpolation(names, 1.0, {STIFFEN_TIME!r})


def wait_until_free(motion, names):
    """Return once ``names`` hold still, free of every motion task.

    Their commands read {READ_GAP!r} s apart must agree and
    areResourcesAvailable(names) be true, within {STILL_WAIT!r} s; else
    RuntimeError, nothing sent. Another task's movement would be cut off
    (a new command interrupts it) or would run first and leave the arm
    elsewhere than read (a NAO postpones the new command).
    """
    import time

    deadline = time.time() + {STILL_WAIT!r}
    before = motion.getAngles(names, False)
    while True:
        time.sleep({READ_GAP!r})
        now = motion.getAngles(names, False)
        still = max(abs(a - b) for a, b in zip(now, before)) <= {STILL!r}
        if still and motion.areResourcesAvailable(names):
            return
        if time.time() >= deadline:
            raise RuntimeError(
                "the arm is moving, or held by another motion task "
                "(areResourcesAvailable is false), after %g s; nothing was "
                "sent: let that movement end, or stop it, and run this again"
                % {STILL_WAIT!r}
            )
        before = now
'''

__all__ = ["STIFFEN_SOURCE", "STIFFEN_TIME"]
