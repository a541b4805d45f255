"""The motion decision along a path: the winning primitive and every g.

The message is laid out by columns (one list entry per path point, g as one
row of numbers per point in the order of ``candidates``): a reach of 100
points is then about 12 KB of JSON that parses in a fifth of the time a list
of per-point objects took (27 KB), and the decision crosses the bus twice per
plan. :attr:`Decision.points` gives the same content point by point.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

from pydantic import Field, model_validator

from shared.messages.base import OptionalFieldsMessage
from shared.messages.measure_params import MeasureParams
from shared.messages.passing_times import check_passing_times
from shared.messages.sample_times import check_times
from shared.primitives import BY_NAME
from shared.robot.side import Side, SideAnyCase

#: A primitive matrix e as nested lists (rows P, R, PR; columns S, E, W).
MatrixRows = tuple[tuple[int, int, int], tuple[int, int, int], tuple[int, int, int]]


class PointDecision(NamedTuple):
    """The decision at one path point (equation 10), read from a ``Decision``.

    Attributes:
        primitive: The winner's name, e.g. ``"S_R E_P W_P"``.
        matrix: The winner's primitive matrix e.
        g: Accumulated mutual information g of every candidate, by name [nat].
    """

    primitive: str
    matrix: MatrixRows
    g: dict[str, float]


class Decision(OptionalFieldsMessage):
    """Decisions for every point of a wrist path.

    Attributes:
        arm: Which arm.
        times: Path times [s], shape (n,).
        primitives: The winner at each point (the primitive that drives the
            arm there), shape (n,).
        candidates: The primitives g is given for, in the order of each row
            of ``g``, shape (c,).
        g: Accumulated mutual information of every candidate at each point
            [nat], shape (n, c).
        matrices: The primitive matrix e of every primitive in
            ``primitives``, by name.
        measures: The IK measures' weights the path was tracked with while
            deciding (the request's, else the motion model's).
        trajectory_times: When the planned trajectory passes each point [s
            from its first sample], shape (n,), non-decreasing: the path's
            own ``times`` are its nominal clock (each reach's from 0), the
            timing stage sets the pace and the rests. Set by the planner
            once the trajectory is timed (the decisions it publishes);
            ``None`` (left out of the JSON, which is then what it was before
            the field existed): not known, as from the decide stage.
        model: The digest of the motion model that decided (12 hex digits
            of its JSON's SHA-256, ``services.fit.model_state.digest``, as
            the fit and decide services log it). Set by the decide stage;
            ``None`` (left out of the JSON): not known, as in recordings
            made before the field existed.
    """

    omitted_when_none = ("trajectory_times", "model")

    arm: SideAnyCase
    times: list[float] = Field(min_length=1)
    primitives: list[str]
    candidates: list[str] = Field(min_length=1)
    g: list[list[float]]
    matrices: dict[str, MatrixRows]
    measures: MeasureParams = Field(default_factory=MeasureParams)
    trajectory_times: list[float] | None = None
    model: str | None = Field(default=None, pattern="^[0-9a-f]{12}$")

    @model_validator(mode="after")
    def _consistent(self) -> Decision:
        n = len(self.times)
        if len(self.primitives) != n or len(self.g) != n:
            raise ValueError(
                f"{n} times but {len(self.primitives)} primitives and "
                f"{len(self.g)} rows of g: one of each per time"
            )
        check_times(self.times)
        _check_names("candidates", self.candidates)
        if len(set(self.candidates)) != len(self.candidates):
            raise ValueError("candidates: a primitive is named twice")
        width = len(self.candidates)
        for k, row in enumerate(self.g):
            if len(row) != width:
                raise ValueError(
                    f"g[{k}] has {len(row)} values, expected {width}: one per candidate"
                )
        _check_names("primitives", self.primitives)
        _check_matrices(self.matrices, set(self.primitives))
        if self.trajectory_times is not None:
            if len(self.trajectory_times) != n:
                raise ValueError(
                    f"{n} times but {len(self.trajectory_times)} trajectory_times: "
                    "one per time"
                )
            check_passing_times(self.trajectory_times, "trajectory_times")
        return self

    @classmethod
    def of_points(
        cls, arm: Side | str, times: Sequence[float], points: Sequence[PointDecision]
    ) -> Decision:
        """The decision of per-point records (every point with the same candidates).

        Raises:
            pydantic.ValidationError: as for any malformed decision.
        """
        candidates = list(points[0].g) if points else []
        return cls.model_validate(
            {
                "arm": arm,
                "times": list(times),
                "primitives": [p.primitive for p in points],
                "candidates": candidates,
                "g": [_row(p.g, candidates) for p in points],
                "matrices": {p.primitive: p.matrix for p in points},
            }
        )

    @property
    def points(self) -> list[PointDecision]:
        """The decision at each point: winner, its matrix, g by candidate name."""
        return [
            PointDecision(
                name, self.matrices[name], dict(zip(self.candidates, row, strict=True))
            )
            for name, row in zip(self.primitives, self.g, strict=True)
        ]


def _row(g: dict[str, float], candidates: list[str]) -> list[float]:
    """g of ``candidates``, in order; NaN (refused) where one is missing."""
    return [g.get(name, math.nan) for name in candidates]


def _check_names(field: str, names: list[str]) -> None:
    """Every name in ``names`` is a known movement primitive."""
    for k, name in enumerate(names):
        if name not in BY_NAME:
            raise ValueError(f"{field}[{k}]: unknown movement primitive {name!r}")


def _check_matrices(matrices: dict[str, MatrixRows], used: set[str]) -> None:
    """One matrix per primitive used, each that primitive's own."""
    missing = sorted(used - set(matrices))
    if missing:
        raise ValueError(f"matrices: no matrix for {missing[0]!r}")
    for name, matrix in matrices.items():
        known = BY_NAME.get(name)
        if known is None:
            raise ValueError(f"matrices: unknown movement primitive {name!r}")
        if matrix != known.matrix:
            raise ValueError(f"matrices: {matrix} is not the matrix of {name!r}")
