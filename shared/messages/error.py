"""The typed error every armplan process sends back instead of a result."""

from __future__ import annotations

from typing import Any

from pydantic import Field

from shared.errors import ArmplanError, error_from_wire
from shared.messages.base import Message


class ErrorReply(Message):
    """A failure, as sent with Zenoh's ``reply_err``.

    Attributes:
        kind: The error's kind, e.g. ``"unreachable_target"``.
        message: Human-readable explanation naming what was wrong.
        evidence: The facts behind it (target, limit, sample index, ...).
    """

    kind: str
    message: str
    evidence: dict[str, Any] = Field(default_factory=dict)

    @classmethod
    def from_error(cls, error: ArmplanError) -> ErrorReply:
        """The reply for a raised error."""
        return cls.model_validate(error.to_wire())

    def to_error(self) -> ArmplanError:
        """The error to raise on the receiving side."""
        return error_from_wire(self.model_dump())
