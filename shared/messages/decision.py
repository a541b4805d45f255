"""The motion decision along a path: the winning primitive and every g."""

from __future__ import annotations

from pydantic import Field, field_validator, model_validator

from shared.messages.base import Message
from shared.primitives import BY_NAME
from shared.robot.side import Side

#: A primitive matrix e as nested lists (rows P, R, PR; columns S, E, W).
MatrixRows = tuple[tuple[int, int, int], tuple[int, int, int], tuple[int, int, int]]


class PointDecision(Message):
    """The decision at one path point (equation 10).

    Attributes:
        primitive: The winner's name, e.g. ``"S_R E_P W_P"``.
        matrix: The winner's primitive matrix e.
        g: Accumulated mutual information g of every candidate, by name [nat].
    """

    primitive: str
    matrix: MatrixRows
    g: dict[str, float]


class Decision(Message):
    """Decisions for every point of a wrist path.

    Attributes:
        arm: Which arm.
        times: Path times [s], shape (n,).
        points: One decision per time.
    """

    arm: Side
    times: list[float] = Field(min_length=1)
    points: list[PointDecision] = Field(min_length=1)

    @model_validator(mode="after")
    def _consistent(self) -> Decision:
        if len(self.times) != len(self.points):
            raise ValueError(
                f"{len(self.times)} times but {len(self.points)} decisions"
            )
        return self

    @field_validator("points")
    @classmethod
    def _known(cls, points: list[PointDecision]) -> list[PointDecision]:
        for k, point in enumerate(points):
            _check_point(k, point)
        return points

    @property
    def primitives(self) -> list[str]:
        """The winning primitive at each point."""
        return [p.primitive for p in self.points]


def _check_point(k: int, point: PointDecision) -> None:
    """Point ``k`` names a known primitive, with its matrix, and known candidates."""
    known = BY_NAME.get(point.primitive)
    if known is None:
        raise ValueError(f"point {k}: unknown movement primitive {point.primitive!r}")
    if point.matrix != known.matrix:
        raise ValueError(
            f"point {k}: matrix {point.matrix} is not that of {point.primitive!r}"
        )
    unknown = [name for name in point.g if name not in BY_NAME]
    if unknown:
        raise ValueError(f"point {k}: g of unknown primitive {unknown[0]!r}")
