"""Request ids: how a caller lets the planner recognise a request it repeats."""

from __future__ import annotations

import uuid

from shared.messages.target import PlanRequest


def with_request_id(request: PlanRequest) -> PlanRequest:
    """``request`` with a fresh random ``request_id`` if it has none.

    With an id, asking again (``Bus.call(..., repeat=True)``) cannot make the
    planner plan or publish the task twice.
    """
    if request.request_id is not None:
        return request
    return request.model_copy(update={"request_id": uuid.uuid4().hex})


def with_new_request_id(request: PlanRequest) -> PlanRequest:
    """``request`` with a fresh random ``request_id``, replacing any it has.

    For a new request built from an old one (a task file copied from a
    recording): its old id would get the old answer, neither planned nor
    published again.
    """
    return request.model_copy(update={"request_id": uuid.uuid4().hex})
