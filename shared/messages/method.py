"""Which planning method: the paper's, or one of the two baselines."""

from __future__ import annotations

from enum import StrEnum


class Method(StrEnum):
    """``mp``: movement primitives + motion decision (the paper's method).

    ``least-norm``: pseudo-inverse IK on all joints, no null-space term.
    ``single``: one performance measure (NTPE) on all joints for the whole
    movement, no primitive decomposition.
    """

    MP = "mp"
    LEAST_NORM = "least-norm"
    SINGLE = "single"
