"""What the hand (NAO's gripper, ``RHand``/``LHand``) does at a reach target.

NAO's hand is one actuator whose value is its open fraction: 0 closed, 1
open (the robot description's ``RHand`` range). A target may carry a hand
action, done during the target's dwell: after the wrist has arrived, before
it leaves (``docs/planning.md``, "The hand").
"""

from __future__ import annotations

from enum import StrEnum

#: Open fraction of a closed hand [-].
CLOSED = 0.0
#: Open fraction of an open hand [-].
OPEN = 1.0


class HandAction(StrEnum):
    """Open or close the hand. The value is the word used in tasks and on the wire."""

    OPEN = "open"
    CLOSE = "close"

    @property
    def goal(self) -> float:
        """The open fraction the action ends at [-]: 1 open, 0 closed."""
        return OPEN if self is HandAction.OPEN else CLOSED

    @property
    def before(self) -> float:
        """The open fraction it starts from when nothing came before [-].

        The other end: a task whose first hand action opens the hand holds
        something in it until then (closed); one whose first action closes
        it is about to grasp (open).
        """
        return CLOSED if self is HandAction.OPEN else OPEN
