"""Stop the arm through the bridge: ``<ns>/bridge/stop``'s request and reply.

Any Zenoh client (a lab's stop button, a GUI, ``armplan stop``) may ask the
bridge to stop the movement it plays: the request is ``{}`` (or an empty
payload), perhaps with the operator's reason. ANY query on the key stops
the arm, whatever its payload: the bridge reads it with
:func:`read_stop_request`, which never refuses (a reason that is no string,
too long or with control characters, an unknown field, a payload that is no
JSON object: the stop is made all the same and the reply's ``note`` says
what was ignored). The reply says what was stopped and whether the arm is
known still (``bridge.service.BridgeService.halt``).
"""

from __future__ import annotations

import json
import unicodedata
from typing import Literal

from pydantic import Field

from shared.messages.base import Message, OptionalFieldsMessage
from shared.text.counted import agreeing, counted

#: Longest reason a stop carries [characters] (it is logged and published):
#: a longer one is cut to it.
MAX_REASON = 200
#: Longest note a reply carries [characters].
MAX_NOTE = 1000
#: A reply's note when the caller's time left was too short to read the arm.
NO_TIME_TO_READ = "no time was left to read the arm settled"


class StopRequest(Message):
    """Stop the movement the bridge plays (an empty payload is ``{}``).

    Attributes:
        reason: Why, in the operator's words, e.g. ``"e-stop button"``:
            logged, and carried in the execution's outcome and error; None
            (left out): none given.
    """

    reason: str | None = Field(default=None, min_length=1, max_length=MAX_REASON)


class StopReply(OptionalFieldsMessage):
    """What ``bridge/stop`` stopped, and whether the arm is known still.

    Attributes:
        playing: A movement (the approach to a trajectory's start, or the
            trajectory) was playing on the robot when the stop came.
        stopped: An execution was being served and the stop ordered it
            stopped: it ended stopped (its caller got the typed error
            ``robot_state`` with ``stopped``, and ``bridge/outcome`` says
            ``"stopped"``), or had not ended yet when the reply was sent
            (``ended`` False: ordered, not yet confirmed). False: none was
            served, or it ended otherwise first (on its own, or with an
            error: see ``note``).
        ended: Whether that execution had ended when the reply was sent;
            None (left out) if none was served.
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
        still: The arm is known still: nothing the bridge sent may still
            move it, and its measured angles were read settled after the
            stop. False: not known (not settled within the wait, the robot
            not answering, the bridge still stopping a call it gave up, or
            an execution that ended with the robot unreachable mid-movement
            and not seen still since): look at the robot.
        waited: How long the stop took, from its arrival to the reply [s].
        reason: The reason the request gave (cleaned); None (left out) if
            none.
        note: What the bridge ignored in the request, or why the arm is not
            known still; None (left out): nothing to say.
    """

    omitted_when_none = (
        "ended",
        "arm",
        "phase",
        "played",
        "phase_duration",
        "reason",
        "note",
    )

    playing: bool
    stopped: bool
    ended: bool | None = None
    arm: str | None = None
    phase: Literal["approach", "trajectory"] | None = None
    played: float | None = Field(default=None, ge=0.0)
    phase_duration: float | None = Field(default=None, ge=0.0)
    dropped: int = Field(default=0, ge=0)
    still: bool = True
    waited: float = Field(default=0.0, ge=0.0)
    reason: str | None = None
    note: str | None = Field(default=None, max_length=MAX_NOTE)


def clean_reason(text: str) -> tuple[str | None, list[str]]:
    """``text`` fit to log and publish: the reason, and what was done to it.

    Control and format characters (a NUL, a line break that would forge a
    log line, a bidirectional override) become a space or go; surrounding
    spaces go; a reason longer than :data:`MAX_REASON` is cut to it. An
    empty reason is none (None).
    """
    problems = []
    unwanted = [ch for ch in text if _unwanted(ch)]
    kept = "".join(
        (" " if ch.isspace() else "") if _unwanted(ch) else ch for ch in text
    )
    if unwanted:
        problems.append(
            f"{counted(len(unwanted), 'control character')} in the reason "
            f"{agreeing(len(unwanted), 'was', 'were')} removed"
        )
    kept = kept.strip()
    if len(kept) > MAX_REASON:
        problems.append(
            f"the reason was cut to {MAX_REASON} of its {len(kept)} characters"
        )
        kept = kept[:MAX_REASON]
    return (kept or None), problems


def _unwanted(ch: str) -> bool:
    """A control or format character, or a line or paragraph separator."""
    category = unicodedata.category(ch)
    return category[0] == "C" or category in ("Zl", "Zp")


def read_stop_request(data: bytes) -> tuple[StopRequest, list[str]]:
    """The stop asked for by ``data`` (a query's payload); never refuses.

    Returns:
        The request (its reason cleaned by :func:`clean_reason`, or None),
        and what was ignored or changed in ``data``, for the reply's
        ``note`` and the log.
    """
    if not data.strip():
        return StopRequest(), []
    try:
        given = json.loads(data)
    except (ValueError, RecursionError):
        return StopRequest(), ["the request is not JSON: it was ignored"]
    if not isinstance(given, dict):
        kind = "null" if given is None else type(given).__name__
        return StopRequest(), [f"the request is a JSON {kind}, not an object: ignored"]
    problems = []
    others = sorted(str(name) for name in given if name != "reason")
    if others:
        shown = ", ".join(repr(name[:40]) for name in others[:5])
        problems.append(f"unknown fields ignored: {shown}")
    reason = given.get("reason")
    if reason is None:
        return StopRequest(), problems
    if not isinstance(reason, str):
        problems.append(f"the reason is a JSON {type(reason).__name__}: ignored")
        return StopRequest(), problems
    cleaned, changed = clean_reason(reason)
    if not cleaned and not changed:
        problems.append("the reason is empty: ignored")
    return StopRequest(reason=cleaned), problems + changed
