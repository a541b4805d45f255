"""Units in the bridge's messages: radians for a joint, an open fraction for a hand.

A refusal names the value and the limit it broke in the actuator's own
units: a joint's angle [rad] and its derivatives [rad/s, rad/s^2, rad/s^3],
or a hand's open fraction (no unit) and its derivatives [/s, /s^2, /s^3].
"""

from __future__ import annotations

from bridge.timeline_keys import is_hand

#: Units of a joint's angle and of its first three derivatives.
JOINT_UNITS = (" rad", " rad/s", " rad/s^2", " rad/s^3")
#: Units of a hand's open fraction (none) and of its first three derivatives.
HAND_UNITS = ("", " /s", " /s^2", " /s^3")


def unit(name: str, order: int = 0) -> str:
    """The unit of actuator ``name``'s ``order``-th derivative, with a leading space.

    Empty for a hand's open fraction (order 0), which has none.
    """
    return (HAND_UNITS if is_hand(name) else JOINT_UNITS)[order]


def value_name(name: str) -> str:
    """What actuator ``name``'s value is: ``"angle"``, or ``"open fraction"``."""
    return "open fraction" if is_hand(name) else "angle"
