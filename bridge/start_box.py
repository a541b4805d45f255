"""The script box that brings the arm to a behavior's start before its timeline.

A Choregraphe timeline plays its first key at 0 s (``bridge.timeline_keys``):
played from anywhere else (NAO's rest posture, the end of another
behavior), the runtime would ask the arm to be at the start at once, and
from rest the demo's RShoulderPitch would need almost five times its speed
limit to reach the next key. The behavior therefore starts with a Python
script box, as Choregraphe behaviors do, which stiffens the arm's joints (and
the hand, for a trajectory that moves it: ``bridge.hand``) and moves them to
the start posture with ``ALMotion.angleInterpolationWithSpeed`` at
``START_SPEED`` of their speed limits (as ``play.py`` does), then fires its
``onStopped`` output, linked to the timeline box's ``onStart``. Stopped
before it is there, it does not start the timeline.

The box's class is what Choregraphe's Python boxes are (``MyClass``
deriving from the runtime's ``GeneratedClass``, ``ALProxy`` given by the
runtime, Python 2 and 3).
"""

from __future__ import annotations

from collections.abc import Sequence

from bridge.python_export import START_SPEED

_SCRIPT = '''class MyClass(GeneratedClass):
    """Bring the arm to the timeline's first key slowly, then start the timeline."""

    def __init__(self):
        GeneratedClass.__init__(self)

    def onLoad(self):
        self.motion = ALProxy("ALMotion")

    def onUnload(self):
        pass

    def onInput_onStart(self):
        names = {names}
        start = {start}  # the timeline's first key [rad]
        self.motion.setStiffnesses(names, 1.0)
        self.motion.angleInterpolationWithSpeed(names, start, {speed})
        self.onStopped()

    def onInput_onStop(self):
        self.onUnload()
'''


def start_script(names: Sequence[str], start: Sequence[float]) -> str:
    """The box's Python: move ``names`` to ``start`` [rad], then ``onStopped``."""
    return _SCRIPT.format(
        names="[" + ", ".join(f'"{name}"' for name in names) + "]",
        start="[" + ", ".join(repr(float(v)) for v in start) + "]",
        speed=START_SPEED,
    )
