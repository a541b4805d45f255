"""Stops ordered together on ``bridge/stop``, and one reply's batch of them.

:class:`OrderedStops` notes what one stop found (the execution it ordered
stopped, the follower's trajectories it dropped); :func:`merged` makes the
stops one reply answers (ordered in turn) one.
"""

from __future__ import annotations

from dataclasses import dataclass

from bridge.serving import Serving


@dataclass(frozen=True)
class OrderedStops:
    """Stops ordered together (:meth:`~bridge.stop_desk.StopDesk.order_stop`).

    Attributes:
        at: When the first was ordered [s, monotonic].
        serving: What the execution served had done then; None: none was.
        dropped: Waiting trajectories the follower dropped.
        reason: The first reason given (cleaned); None: none.
        notes: What was ignored in their requests.
    """

    at: float
    serving: Serving | None
    dropped: int
    reason: str | None
    notes: list[str]


def merged(batch: list[OrderedStops]) -> OrderedStops:
    """The stops of ``batch`` (ordered in turn) as one: the last execution stopped."""
    serving = next((o.serving for o in reversed(batch) if o.serving), None)
    first = next(
        (
            o
            for o in batch
            if serving is not None
            and o.serving is not None
            and o.serving.order is serving.order
        ),
        batch[0],
    )
    notes: list[str] = []
    for ordered in batch:
        notes += [n for n in ordered.notes if n not in notes]
    return OrderedStops(
        first.at,
        serving,
        sum(o.dropped for o in batch),
        next((o.reason for o in batch if o.reason is not None), None),
        notes,
    )
