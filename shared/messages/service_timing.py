"""What a service spent on one request, sent back beside its reply."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import Message


class ServiceTiming(Message):
    """Where one request's time went inside the service that answered it.

    A service sends it as the Zenoh attachment of each reply (JSON), never in
    the reply's payload, so the reply's JSON stays the same; a caller may read
    it (``Bus.call_timed``) to tell the service's own work from the trips
    through Zenoh. Wall-clock durations on the service's machine.

    Attributes:
        parse: Validating the request's JSON [s].
        handle: The service's function on the request [s].
        reply_json: Writing the reply's JSON [s].
    """

    parse: float = Field(ge=0.0)
    handle: float = Field(ge=0.0)
    reply_json: float = Field(ge=0.0)

    @property
    def total(self) -> float:
        """All of the request's time inside the service [s]."""
        return self.parse + self.handle + self.reply_json
