"""Stop the arm through the bridge: ``<ns>/bridge/stop``'s request and reply.

Any Zenoh client (a lab's stop button, a GUI, ``armplan stop``) may ask the
bridge to stop the movement it plays: the request is ``{}`` (or an empty
payload), perhaps with the operator's reason; the reply comes once the arm
is still, and says what was stopped (``bridge.service.BridgeService.halt``).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from shared.messages.base import Message, OptionalFieldsMessage

#: Longest reason a stop may carry [characters] (it is logged and published).
MAX_REASON = 200


class StopRequest(Message):
    """Stop the movement the bridge plays (an empty payload is ``{}``).

    Attributes:
        reason: Why, in the operator's words, e.g. ``"e-stop button"``:
            logged, and carried in the execution's outcome and error; None
            (left out): none given.
    """

    reason: str | None = Field(default=None, min_length=1, max_length=MAX_REASON)


class StopReply(OptionalFieldsMessage):
    """What ``bridge/stop`` stopped; sent once the arm is still.

    Attributes:
        playing: A movement (the approach to a trajectory's start, or the
            trajectory) was playing on the robot when the stop came.
        stopped: An execution was being served and the stop ended it (its
            caller got the typed error ``robot_state`` with ``stopped``, and
            ``bridge/outcome`` says ``"stopped"``); False: none was, or it
            ended on its own first.
        arm: The arm of that execution, ``"right"`` or ``"left"``; None (left
            out) if none was being served.
        phase: Where it was stopped: ``"approach"`` (nothing of the
            trajectory was sent) or ``"trajectory"``; None (left out) if no
            movement had been sent yet, or none was stopped.
        played: Time into that phase when the arm was stopped, about [s];
            None (left out) unless known.
        phase_duration: That phase's length [s]; None (left out) unless known.
        dropped: Trajectories waiting in the follower (``--follow``) that
            were dropped: they arrived before the stop.
        still: The arm is still: the stopped execution has ended and its
            measured angles settled (with nothing stopped: the bridge moves
            nothing). False: it did not settle within the stop's wait.
        waited: How long the stop took, from its arrival to the reply [s].
        reason: The reason the request gave; None (left out) if none.
    """

    omitted_when_none = ("arm", "phase", "played", "phase_duration", "reason")

    playing: bool
    stopped: bool
    arm: str | None = None
    phase: Literal["approach", "trajectory"] | None = None
    played: float | None = Field(default=None, ge=0.0)
    phase_duration: float | None = Field(default=None, ge=0.0)
    dropped: int = Field(default=0, ge=0)
    still: bool = True
    waited: float = Field(default=0.0, ge=0.0)
    reason: str | None = None
