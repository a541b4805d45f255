"""A timed wrist path in the torso frame."""

from __future__ import annotations

import statistics
from itertools import pairwise

from pydantic import Field, model_validator

from shared.messages.base import Direction, FieldError, Message, Vec3
from shared.messages.sample_times import check_times
from shared.messages.seconds import DIVIDE, not_seconds
from shared.robot.side import Side, SideAnyCase
from shared.text.counted import counted

#: Most samples one path may hold: 100 Hz for 10 minutes (``MAX_DURATION``),
#: both ends included.
MAX_SAMPLES = 60_001
#: Fewest samples a path may hold: a start and an end. One sample has no
#: step to time the movement by: it was planned as a 0 s "trajectory", a
#: single far posture (``armplan plan --wrist-path`` of a one-row CSV).
MIN_SAMPLES = 2
#: Longest a path may last, first sample to last [s] (10 minutes).
MAX_DURATION = 600.0
#: What to do with a path whose times look like milliseconds (or that is
#: in seconds but sampled less than once a second).
MILLISECONDS_FIX = f"{DIVIDE}, or, if they are seconds, give a sample every 1 s or less"


class WristPath(Message):
    """Wrist positions at strictly increasing times.

    Attributes:
        arm: Which arm's wrist (any case: ``"Left"`` reads as ``"left"``);
            left out: the right arm's, or in a ``PlanRequest`` its ``arm``.
        times: Sample times from the movement's start [s], shape (n,),
            at least ``MIN_SAMPLES`` of them: the first is 0 (a path in
            clock time, or starting at t = 1 s, is refused: the planner
            keeps its times, they are the trajectory's), strictly
            increasing; sampled
            at 1 to 10 000 Hz (median step), so that times in milliseconds
            are refused as such (``shared.messages.seconds``), not taken
            for a path a thousand times slower.
        positions: Wrist positions in the torso frame [m], shape (n, 3).
        palm: Optional palm direction to turn towards along the path (unit
            vector; by the roll about the forearm only, as ``ReachTarget``).
    """

    arm: SideAnyCase = Side.RIGHT
    times: list[float] = Field(min_length=1, max_length=MAX_SAMPLES)
    positions: list[Vec3] = Field(min_length=1, max_length=MAX_SAMPLES)
    palm: Direction | None = None

    @model_validator(mode="after")
    def _consistent(self) -> WristPath:
        if len(self.times) != len(self.positions):
            raise FieldError(
                "positions",
                f"{len(self.times)} times but {len(self.positions)} positions",
            )
        check_times(self.times)
        if problem := too_few_samples(len(self.times), "this one"):
            raise FieldError("times", problem)
        if self.times[0] != 0.0:
            raise FieldError(
                "times",
                f"the path starts at t = {self.times[0]:.9g} s, not 0: times are "
                "from the movement's start (the trajectory keeps them); subtract "
                "the first time from every time",
            )
        step = statistics.median(b - a for a, b in pairwise(self.times))
        problem = not_seconds(step, "the wrist path", "wrist paths", MILLISECONDS_FIX)
        if problem:
            raise FieldError("times", problem)
        if self.times[-1] - self.times[0] > MAX_DURATION:
            raise FieldError(
                "times",
                f"the path lasts {self.times[-1] - self.times[0]:g} s, longer than "
                f"{MAX_DURATION:g} s (from t = {self.times[0]:g} s to "
                f"t = {self.times[-1]:g} s)",
            )
        return self


def too_few_samples(count: int, whose: str) -> str:
    """Why a path of ``count`` samples is refused; ``""`` if it is not.

    Args:
        count: How many samples the path holds.
        whose: Who holds them, for the message: ``"this one"``, a file's name.
    """
    if count >= MIN_SAMPLES:
        return ""
    return (
        f"a wrist path needs at least {counted(MIN_SAMPLES, 'sample')}, {whose} "
        f"has {count}: one sample has no step to time the movement by; give "
        "the start and the end (the path must start and end at rest)"
    )
