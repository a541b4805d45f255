"""The script box that brings the arm to a behavior's start before its timeline.

A Choregraphe timeline plays its first key at 0 s (``bridge.timeline_keys``):
played from anywhere else (NAO's rest posture, the end of another
behavior), the runtime would ask the arm to be at the start at once, and
from rest the demo's RShoulderPitch would need almost five times its speed
limit to reach the next key. The behavior therefore starts with a Python
script box, as Choregraphe behaviors do, which stiffens the arm's joints (and
the hand, for a trajectory that moves it: ``bridge.hand``) where they are (a
limp arm's command first moved to where it hangs, so it does not snap back;
a robot not awake refused: ``bridge.script_stiffen``), moves them to the
start posture with ``ALMotion.angleInterpolation`` of minimum-jerk keys
within ``START_SPEED`` of their speed, acceleration and jerk limits
(``bridge.script_approach``, as ``play.py`` does; keys that would bring the
arm near the body, or near the other arm where the robot measures it, are
refused before anything moves, and so is a timeline whose keys would: a plan
made without ``other_arm`` knows nothing of that arm), then, once the arm's
command is at the start (``check_arrived``: a move another client ended
is refused), fires its ``onStopped`` output, linked to the timeline box's
``onStart``. Refused,
``onInput_onStart`` raises ``RuntimeError`` (the runtime reports the box's
error) and ``onStopped`` does not fire: the timeline never starts.

Stopped before the arm is there (its ``onStop`` input: the behavior is
stopped), the box ends the move with ``ALMotion.killTasksUsingResources``
on its joints (they hold where they are) and does not fire ``onStopped``,
so the timeline never starts. It sends that stop every ``STOP_PERIOD``
until the move's call has returned: a stop the robot serves before the move
has taken effect ends nothing (``bridge.stopper``). A box stopped before it
sends the move does not send it.

The box's class is what Choregraphe's Python boxes are (``MyClass``
deriving from the runtime's ``GeneratedClass``, ``ALProxy`` given by the
runtime, Python 2 and 3).
"""

from __future__ import annotations

from collections.abc import Sequence

from bridge.python_export import START_SPEED
from bridge.script_approach import approach_source
from bridge.script_stiffen import STIFFEN_SOURCE
from shared.robot import Side

#: Time between the stops the box sends when stopped [s]: ALMotion's cycle.
STOP_PERIOD = 0.02

_SCRIPT = '''class MyClass(GeneratedClass):
    """Bring the arm to the timeline's first key slowly, then start the timeline.

    Stopped on the way (onInput_onStop), it ends the move, where the arm is,
    and does not start the timeline.
    """

    def __init__(self):
        GeneratedClass.__init__(self)
        self.joint_names = {names}
        self.first_key = {start}  # the timeline's first key [rad]
        self.timeline = {timeline}  # its keys: one list per joint [rad]
        self.timeline_times = {timeline_times}  # theirs [s]
        self.stopping = False
        self.moving = False

    def onLoad(self):
        self.motion = ALProxy("ALMotion")

    def onUnload(self):
        pass

    def onInput_onStart(self):
        self.stopping = False
        self.moving = True
        try:
            stiffen_where_it_is(self.motion, self.joint_names)
            if not self.stopping:
                now = self.motion.getAngles(self.joint_names, False)
                others = other_arm_parts(self.motion.getAngles(OTHER_JOINTS, True))
                keys, times = approach_keys(
                    self.joint_names, now, self.first_key, {speed}, others
                )
                check_clear(
                    self.joint_names,
                    self.timeline,
                    self.timeline_times,
                    "the timeline",
                    others,
                    OTHER_ARM_ADVICE,
                )
                self.motion.angleInterpolation(self.joint_names, keys, times, True)
                now = self.motion.getAngles(self.joint_names, False)
                check_arrived(self.joint_names, now, self.first_key)
        except Exception:  # ended by onInput_onStop, or refused
            if not self.stopping:
                raise
        finally:
            self.moving = False
        if not self.stopping:
            self.onStopped()

    def onInput_onStop(self):
        # End the move until onInput_onStart has seen it end: a stop served
        # before the move has taken effect would end nothing.
        import time

        self.stopping = True
        while self.moving:
            self.motion.killTasksUsingResources(self.joint_names)
            time.sleep({period})
        self.onUnload()
'''


def start_script(
    names: Sequence[str],
    timeline: Sequence[Sequence[float]],
    times: Sequence[Sequence[float]],
) -> str:
    """The box's Python: move ``names`` to the timeline's start, then ``onStopped``.

    ``timeline``: the keys the timeline plays, one sequence per joint of
    ``names`` [rad; a hand's open fraction], ``times`` theirs [s]; the
    first key of each is the start. Its ``onStop`` ends the move and keeps
    ``onStopped`` from firing. The class is followed by the
    ``stiffen_where_it_is``, ``approach_keys`` and ``check_clear`` it calls
    (``bridge.script_stiffen``, ``bridge.script_approach``).
    """
    box = _SCRIPT.format(
        names="[" + ", ".join(f'"{name}"' for name in names) + "]",
        start=_floats([joint[0] for joint in timeline]),
        timeline="[" + ", ".join(_floats(joint) for joint in timeline) + "]",
        timeline_times="[" + ", ".join(_floats(joint) for joint in times) + "]",
        speed=START_SPEED,
        period=STOP_PERIOD,
    )
    side = Side.LEFT if names[0].startswith("L") else Side.RIGHT
    return box + STIFFEN_SOURCE + approach_source(side)


def _floats(values: Sequence[float]) -> str:
    """``values`` as a Python list, each written in full."""
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"
