"""The answering of ``<ns>/bridge/stop`` queries: the operator's stop over Zenoh.

ANY query on it stops the arm: :meth:`StopDesk.order_stop`
(:meth:`BridgeService.order_stop <bridge.service.BridgeService.order_stop>`)
runs on Zenoh's thread as the query arrives (``Endpoint.at_once``), before
the payload is parsed (leniently) or the caller's deadline looked at: the
execution being served is ordered stopped (``bridge.stop_order``; a
movement playing has its arm's motion tasks killed at once,
``ALMotion.killTasksUsingResources``), its caller gets the robot's usual
"stopped" error, ``bridge/outcome`` says ``"stopped"`` (by
``bridge/stop``), and the follower's waiting trajectories are dropped; an
execute query that arrived before the stop (queued, or being checked) is
stopped as it takes the robot, nothing of it sent. Then
:meth:`StopDesk.answer_stop`, on a worker of its own (never queued behind
an execute query, never refused busy), sends the
:class:`~shared.messages.StopReply` once the stopped execution has ended,
saying whether the arm is known still (never when that is not known, nor
while a trajectory that came after the stop holds the robot). A stop is
not a latch: an execute query after it plays.

:class:`StopDesk` owns the stop's state: the stops ordered and not yet
answered, the last reply's batch and time, and every arm not known still
since an execution on it ended with an error mid-movement (the execute
path marks each, :meth:`StopDesk.mark_unsure` and :meth:`StopDesk.mark_sure`).
The stops one reply answers are :mod:`bridge.ordered_stops`; the arm is
read settled by :mod:`bridge.settled`.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from typing import Any

from bridge.at_rest import READ_GAP
from bridge.ordered_stops import OrderedStops, merged
from bridge.playback import HALT_WAIT, LOST_AFTER
from bridge.robot_bridge import RobotBridge
from bridge.serving import Serving, Slot
from bridge.settled import not_settled
from bridge.stop_order import STOPPED_BY
from shared.bus import Bus
from shared.bus.arrival import current_arrival
from shared.bus.deadline import REPLY_MARGIN, Due, current_due
from shared.bus.robot_routes import STOP
from shared.messages import ExecutionOutcome, StopReply, StopRequest
from shared.messages.stop import MAX_NOTE, NO_TIME_TO_READ, read_stop_request
from shared.robot import Side

log = logging.getLogger("armplan.bridge")
#: Longest wait for the stopped execution to end [s]: its next step (a
#: reading, or a check before its movement: the arm's rest, up to a
#: second, and stiffening), then the stop's answer (``HALT_WAIT``).
HALT_END_WAIT = 2.0 * LOST_AFTER + HALT_WAIT + 1.0
#: Longest wait for the stopped arm's measured angles to settle [s].
SETTLE_WAIT = 1.0

#: Called by a stop with its time [s, monotonic]; drops what waits from
#: before it and returns how many it dropped (the follower's queue).
DropWaiting = Callable[[float], int]


class StopDesk:
    """The bridge's ``bridge/stop``: orders stops, answers them.

    Attributes:
        bus: Whose key names the stop in the log.
        robot: The robot-facing bridge (its client reads the arm still).
    """

    def __init__(self, bus: Bus, robot: RobotBridge, slot: Slot) -> None:
        self.bus = bus
        self.robot = robot
        self._slot = slot  # the service's: the request being served
        self._on_halt: list[DropWaiting] = []
        self._lock = threading.Lock()  # guards the five below
        self._orders: list[OrderedStops] = []  # ordered, not yet answered
        self._last: OrderedStops | None = None  # what the last reply answered
        self._last_latest = -float("inf")  # [s, monotonic] the last of them
        #: The arms of executions that ended with an error mid-movement and
        #: have not been read still since (a stop does not say they are
        #: still), each with the number of its mark: a read that began
        #: before a newer mark does not clear it.
        self._unsure: dict[str, int] = {}
        self._marks = 0

    def on_halt(self, drop: DropWaiting) -> None:
        """Have every ``bridge/stop`` call ``drop`` (the follower's queue)."""
        self._on_halt.append(drop)

    def mark_unsure(self, arm: str) -> None:
        """An execution on ``arm`` ended with an error mid-movement: it may move on."""
        with self._lock:
            self._marks += 1
            self._unsure[arm] = self._marks

    def mark_sure(self, arm: str) -> None:
        """An execution on ``arm`` played to its end: no longer unsure."""
        with self._lock:
            self._unsure.pop(arm, None)

    def order_stop(self, payload: bytes) -> None:
        """Order the stop a ``bridge/stop`` query asks, as it arrives.

        Run on Zenoh's thread for every query on ``bridge/stop``
        (``Endpoint.at_once``), before its payload is parsed, its deadline
        looked at or it is queued: whatever the payload (read leniently,
        :func:`~shared.messages.stop.read_stop_request`) and whatever the
        caller's time left, the arm is stopped; only the reply (its wait
        for the arm to be still) is queued. Only a lock and an event: it
        never waits for the robot. The stop's time is the query's arrival
        (:func:`~shared.bus.arrival.current_arrival`): a request that
        arrived before it is stopped, one after it is not.
        """
        arrived = current_arrival()
        at = time.monotonic() if arrived is None else arrived
        try:
            request, notes = read_stop_request(payload)
        except Exception:  # never keeps the arm from being stopped
            log.exception("stop: could not read the request; stopping anyway")
            request, notes = StopRequest(), ["the request could not be read"]
        self._order(request.reason, notes, at)

    def _order(self, reason: str | None, notes: list[str], at: float) -> None:
        """Order the execution served stopped; drop what waits; note it."""
        dropped = 0
        for drop in self._on_halt:
            try:
                dropped += drop(at)
            except Exception:  # the execution is stopped all the same
                log.exception("stop: could not drop the waiting trajectories")
        serving = self._slot.halt(reason, at)
        with self._lock:
            self._orders.append(OrderedStops(at, serving, dropped, reason, notes))
        log.warning(
            "stop: asked on %s (reason: %r); %s; %d waiting trajectories dropped%s",
            self.bus.key(STOP.path),
            reason,
            "nothing was being played"
            if serving is None
            else "stopping the movement playing"
            if serving.moving
            else "stopping the execution before its movement",
            dropped,
            "".join(f"; {note}" for note in notes),
        )

    def halt(self, request: StopRequest) -> StopReply:
        """Stop the execution being served, drop what waits; say if still.

        :meth:`order_stop` with ``request``'s reason, then
        :meth:`answer_stop`: the two halves of a ``bridge/stop`` query.
        """
        self._order(request.reason, [], time.monotonic())
        return self.answer_stop(request)

    def answer_stop(self, request: StopRequest) -> StopReply:
        """The reply to the ``bridge/stop`` queries ordered since the last one.

        The execution being served when the stop came (if any) was ordered
        stopped (:meth:`order_stop`): a movement playing has its arm's
        motion tasks killed at once (``killTasksUsingResources``, again
        until its call has ended), one not sent yet is not sent; its caller
        gets the robot's "stopped" error (``robot_state``) and
        ``bridge/outcome`` says ``"stopped"`` by ``bridge/stop``. The
        follower's waiting trajectories that arrived before the stop were
        dropped. The reply waits for that execution to end (at most
        :data:`HALT_END_WAIT`, and no longer than the caller's time left
        allows), then says whether the arm is known still (:meth:`_still`,
        at most :data:`SETTLE_WAIT` more). Stops that came together (one
        queued while another was answered) get one reply. Idempotent; not
        a latch: the next execute query plays.
        """
        arrived = current_arrival()  # this reply's first query's
        with self._lock:
            batch, self._orders = self._orders, []
        if arrived is not None:  # a stop whose query was never answered here
            stale = [o for o in batch if o.at < arrived]  # (e.g. refused)
            batch = [o for o in batch if o.at >= arrived]
            if stale:
                log.warning("stop: %d earlier stops had no reply", len(stale))
        if not batch:  # answered with an earlier reply's batch
            with self._lock:
                last = self._last
                latest = self._last_latest
            if last is not None and arrived is not None and latest < arrived:
                last = None  # earlier queries' only, not this one's
            if last is None:  # called without order_stop: order it now
                self._order(request.reason, [], time.monotonic())
                with self._lock:
                    batch, self._orders = self._orders, []
            else:
                batch = [last]
        stop = merged(batch)
        with self._lock:
            self._last = stop
            self._last_latest = max(self._last_latest, *(o.at for o in batch))
        due = current_due()
        if due is not None and due.passed:  # gone, or its clock is behind:
            due = None  # a full answer, for one that still waits
        reply = self._reply(stop, due)
        log.warning("stop: answered %s", reply.to_json())
        return reply

    def _reply(self, stop: OrderedStops, due: Due | None) -> StopReply:
        """Wait for ``stop``'s execution to end (if any); say if the arm is still."""
        serving = stop.serving
        notes = list(stop.notes)
        fields: dict[str, Any] = {}
        arm: str | None = None
        ended = True
        stopped = False
        after: Serving | None = None  # what holds the robot after the stopped
        if serving is not None:
            give_up = stop.at + HALT_END_WAIT
            if due is not None:
                give_up = min(give_up, due.at - REPLY_MARGIN - SETTLE_WAIT)
            left = self._slot.wait_free(
                lambda _serving, _now: give_up, gone=serving.order
            )
            ended = left is None or left.order is not serving.order
            if left is not None and ended:  # another took the robot since
                after = left
            outcome = serving.order.outcome
            arm = serving.arm
            if ended and outcome is not None:
                arm = outcome.arm
                stopped = outcome.outcome == "stopped" and (
                    outcome.stopped_by == STOPPED_BY
                )
                if stopped:
                    fields = {
                        "phase": outcome.phase,
                        "played": outcome.played,
                        "phase_duration": outcome.phase_duration,
                    }
                else:
                    notes.append(_ended_otherwise(outcome))
            elif ended:  # it failed unexpectedly (logged by the service host)
                notes.append("the execution ended with an unexpected failure")
            else:  # ordered stopped; its end not seen before the reply
                stopped, ended = True, False
                notes.append(
                    "the execution had not ended when the reply was sent "
                    f"({time.monotonic() - stop.at:.2f} s after the stop): "
                    "the stop is ordered, not yet confirmed"
                )
                if serving.sent is not None:
                    fields = {"phase": "trajectory", "phase_duration": serving.duration}
                elif serving.moving:
                    fields = {"phase": "approach"}
        if after is not None:  # it moves the arm, or may: never "still"
            still = False
            notes.append(
                "a trajectory that came after the stop is playing"
                if not after.order.ordered
                else "another execution the stop ended had not ended yet"
            )
        else:
            still, why = self._still(arm, ended, due)
            now = self._slot.serving  # one that came after: moves the arm
            if not still and _another(now, serving):
                why = "a trajectory that came after the stop is playing"
            if why:
                notes.append(why)
        note = "; ".join(notes) or None
        if note is not None and len(note) > MAX_NOTE:
            note = note[: MAX_NOTE - 3] + "..."
        return StopReply(
            playing=serving is not None and serving.moving,
            stopped=stopped,
            ended=None if serving is None else ended,
            arm=arm,
            dropped=stop.dropped,
            still=still,
            waited=time.monotonic() - stop.at,
            reason=stop.reason,
            note=note,
            **fields,
        )

    def _still(self, arm: str | None, ended: bool, due: Due | None) -> tuple[bool, str]:
        """Whether the arm is known still, and if not, why.

        Not while the execution stopped has not ended, nor while the client
        still stops a call it gave up (the robot did not answer it: the call
        may yet move the arm). Else the measured angles of ``arm`` (and of
        every arm whose execution ended with an error mid-movement and was
        not seen still since; with neither, both arms) must settle: two
        readings :data:`READ_GAP` apart within
        :data:`~bridge.settled.SETTLED`, read for at most
        :data:`SETTLE_WAIT` (and no longer than the caller's time left
        allows): a robot that does not answer in time is not known still.
        """
        if not ended:
            return False, ""
        if self.robot.client.stopping:
            return False, (
                "the bridge is still stopping the arm after giving up a call "
                "the robot did not answer: it may still move"
            )
        with self._lock:
            unsure = dict(self._unsure)
        arms = ({arm} if arm is not None else set()) | set(unsure)
        arms = arms or {"right", "left"}
        names = [n for a in sorted(arms) for n in Side.parse(a).joint_names]
        wait = SETTLE_WAIT
        if due is not None:
            wait = min(wait, due.at - REPLY_MARGIN - time.monotonic())
        if wait <= READ_GAP:
            return False, NO_TIME_TO_READ
        problem = not_settled(self.robot.client, names, wait)
        if problem:
            log.warning("stop: the arm is not known still: %s", problem)
            return False, problem
        with self._lock:  # the marks read still, not newer ones
            for seen, mark in unsure.items():
                if self._unsure.get(seen) == mark:
                    del self._unsure[seen]
        return True, ""


def _another(now: Serving | None, stopped: Serving | None) -> bool:
    """Whether ``now`` is an execution other than ``stopped``, not ordered stopped."""
    if now is None or now.order.ordered:
        return False
    return stopped is None or now.order is not stopped.order


def stop_request(data: bytes) -> StopRequest:
    """A ``bridge/stop`` payload read leniently (never refused; see ``order_stop``)."""
    return read_stop_request(data)[0]


def _ended_otherwise(outcome: ExecutionOutcome) -> str:
    """Why the execution stopped was not ended by the stop, in a note."""
    if outcome.outcome == "completed":
        return "the execution had played to its end before the stop took effect"
    return (
        f"the execution ended with {outcome.error_kind or outcome.outcome} "
        f"before the stop took effect: {outcome.message}"
    )
