"""A timed wrist path in the torso frame."""

from __future__ import annotations

from pydantic import Field, model_validator

from shared.messages.base import Direction, Message, Vec3
from shared.messages.sample_times import check_times
from shared.robot.side import Side, SideAnyCase

#: Most samples one path may hold (100 Hz for 10 minutes).
MAX_SAMPLES = 60_000
#: Longest a path may last, first sample to last [s] (10 minutes).
MAX_DURATION = 600.0


class WristPath(Message):
    """Wrist positions at strictly increasing times.

    Attributes:
        arm: Which arm's wrist (any case: ``"Left"`` reads as ``"left"``);
            left out: the right arm's, or in a ``PlanRequest`` its ``arm``.
        times: Sample times [s], shape (n,), strictly increasing.
        positions: Wrist positions in the torso frame [m], shape (n, 3).
        palm: Optional palm direction to hold along the path (unit vector).
    """

    arm: SideAnyCase = Side.RIGHT
    times: list[float] = Field(min_length=1, max_length=MAX_SAMPLES)
    positions: list[Vec3] = Field(min_length=1, max_length=MAX_SAMPLES)
    palm: Direction | None = None

    @model_validator(mode="after")
    def _consistent(self) -> WristPath:
        if len(self.times) != len(self.positions):
            raise ValueError(
                f"{len(self.times)} times but {len(self.positions)} positions"
            )
        check_times(self.times)
        if self.times[-1] - self.times[0] > MAX_DURATION:
            raise ValueError(
                f"the path lasts {self.times[-1] - self.times[0]:g} s, longer than "
                f"{MAX_DURATION:g} s (from t = {self.times[0]:g} s to "
                f"t = {self.times[-1]:g} s)"
            )
        return self
