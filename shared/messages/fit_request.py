"""What a client sends the fit service to fit a new motion model."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import Message

#: Most demonstration files one fit may read.
MAX_FILES = 64


class FitRequest(Message):
    """Fit the motion model to demonstration files the fit service can read.

    Attributes:
        files: Demonstration MCAP files (``armplan demos``), relative to the
            fit service's demonstration directory (``$ARMPLAN_DEMOS_DIR``,
            else its working directory); it reads nothing outside it.
        bins: States per motion variable.
        smoothing: Pseudo-count added to every table cell.
    """

    files: list[str] = Field(min_length=1, max_length=MAX_FILES)
    bins: int = Field(default=20, ge=2, le=64)
    smoothing: float = Field(default=1.0, gt=0.0, le=1e6)
