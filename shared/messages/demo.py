"""Human demonstrations: one subject's arm, and one sample of one reach.

A demonstration file (MCAP) holds one ``DemoSubject`` per subject on topic
``demo/subject`` and one ``DemoSample`` per sample on ``demo/sample``, in
recording order. Samples are retargeted to NAO already: positions are in
NAO's torso frame [m] with NAO's shoulder and segment lengths, the human
segment directions kept (``shared.demos.retarget``).
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import AfterValidator, Field

from shared.messages.base import Message, Vec3
from shared.primitives import BY_NAME, MOTION_PRIMITIVES
from shared.robot.side import Side, SideAnyCase

#: A rotation as a unit quaternion (w, x, y, z).
QuaternionTuple = tuple[float, float, float, float]


def _unit_quaternion(q: QuaternionTuple) -> QuaternionTuple:
    norm = math.sqrt(sum(v * v for v in q))
    if norm < 1e-9:
        raise ValueError("a quaternion must not be zero")
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


def _known_primitive(name: str | None) -> str | None:
    """A motion primitive's name (spacing free): the decision's candidates.

    Function primitives (``S_R E_P W_R``, ``W_R``) are not decided from the
    arm's state, so they label no demonstration; ``armplan fit`` failed on
    one with an internal error.
    """
    if name is None:
        return None
    key = " ".join(name.split())
    if key not in BY_NAME:
        raise ValueError(f"unknown movement primitive {name!r}")
    if BY_NAME[key] not in MOTION_PRIMITIVES:
        motion = ", ".join(p.name for p in MOTION_PRIMITIVES)
        raise ValueError(
            f"{key!r} is a function primitive; a demonstration is labelled with "
            f"a motion primitive ({motion})"
        )
    return key


#: A unit quaternion (w, x, y, z), normalised on input.
Quaternion = Annotated[QuaternionTuple, AfterValidator(_unit_quaternion)]


class DemoSubject(Message):
    """The person who made some demonstrations, and the size of their arm.

    Attributes:
        name: The subject's identifier, e.g. ``"S01"``.
        stature: Body height [m], if known.
        upper_arm: Shoulder-to-elbow length L_u of the human arm [m].
        forearm: Elbow-to-wrist length L_f of the human arm [m].
        source: Where the data came from (generator and seed, or file name).
    """

    name: str = Field(min_length=1, max_length=64)
    stature: float | None = Field(default=None, gt=0.0, le=3.0)
    upper_arm: float = Field(gt=0.0, le=1.5)
    forearm: float = Field(gt=0.0, le=1.5)
    source: str = Field(default="", max_length=1000)


class DemoSample(Message):
    """One sample of one demonstrated reach, retargeted to NAO.

    Attributes:
        subject: The subject's identifier (a ``DemoSubject.name``).
        trial: Trial number, unique within the subject; samples of one trial
            are consecutive and their times increase.
        point: Grid point of the paper's protocol (1..16), 0 if none.
        arm: Which arm moved.
        time: Time since the reach started [s].
        shoulder: Shoulder position, NAO torso frame [m].
        elbow: Elbow position, NAO torso frame [m].
        wrist: Wrist position, NAO torso frame [m].
        wrist_orientation: Wrist frame as a unit quaternion (w, x, y, z):
            x along the forearm, y the palm normal of a right hand (a left
            hand's palm faces -y), as NAO's wrist frame; ``None`` if the
            recording does not show the forearm's roll.
        target: Where the wrist is going (its position at the reach's end),
            NAO torso frame [m].
        primitive: The movement primitive moving the arm at this sample, as
            labelled by the synthetic generator; ``None`` for recorded data.
    """

    subject: str = Field(min_length=1, max_length=64)
    trial: int = Field(ge=0)
    point: int = Field(default=0, ge=0, le=1000)
    arm: SideAnyCase = Side.RIGHT
    time: float = Field(ge=0.0)
    shoulder: Vec3
    elbow: Vec3
    wrist: Vec3
    wrist_orientation: Quaternion | None = None
    target: Vec3
    primitive: Annotated[str | None, AfterValidator(_known_primitive)] = None
