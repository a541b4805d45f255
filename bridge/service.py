"""The bridge as a Zenoh service: execute requests in, the robot moves, reports out.

:class:`BridgeService` is the thin wrapper around
:class:`~bridge.robot_bridge.RobotBridge`: it answers ``<ns>/bridge/execute``
(an :class:`~shared.messages.ExecuteRequest` in, the
:class:`~shared.messages.ExecuteReply` with the tracking report out) and
publishes what crosses the robot's boundary: the checked command frames
(``bridge/frames``), each measured joint state while the arm moves
(``bridge/state``), the tracking report (``bridge/report``) and how each
execution ended (``bridge/outcome``: completed; stopped by the robot, in
the approach or the trajectory, at t = X s; or the error's kind), so a
stop is seen on the bus, not only by the caller. A trajectory
with one frame over a limit is refused with the bridge's typed error before
anything is published or sent, even while another plays (its frames are
checked before the robot is asked for). One robot plays one trajectory at
a time: a request that comes while one is playing is refused with
``robot_busy`` (naming about how long is left: the approach's rest too,
once it has started), not queued, so the robot never starts a
movement its caller may have given up on; nor one its caller will give up
on before it ends: a query whose caller's time left cannot cover the
approach and the trajectory is refused with ``caller_deadline``, at once,
and again after the approach if that took longer (``bridge.in_time``).
The follower (``--follow``) waits instead: it plays the planner's
trajectories in order by design.

``<ns>/bridge/stop`` is the operator's stop over Zenoh. ANY query on it
stops the arm: :meth:`BridgeService.order_stop` runs on Zenoh's thread as
the query arrives (``Endpoint.at_once``), before the payload is parsed
(leniently) or the caller's deadline looked at: the execution being served
is ordered stopped (``bridge.stop_order``; a movement playing has its
arm's motion tasks killed at once, ``ALMotion.killTasksUsingResources``),
its caller gets the robot's usual "stopped" error, ``bridge/outcome`` says
``"stopped"`` (by ``bridge/stop``), and the follower's waiting trajectories
are dropped; an execute query that arrived before the stop (queued, or
being checked) is stopped as it takes the robot, nothing of it sent.
Then :meth:`BridgeService.answer_stop`, on a worker of its own (never
queued behind an execute query, never refused busy), sends the
:class:`~shared.messages.StopReply` once the stopped execution has ended,
saying whether the arm is known still (never when that is not known, nor
while a trajectory that came after the stop holds the robot). A stop is
not a latch: an execute query after it plays.

Run it with ``python -m bridge.serve --robot URL`` (``armplan up
--with-sim`` and ``armplan demo`` do); see :mod:`bridge.serve`.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import zenoh

from bridge.at_rest import READ_GAP, until_still
from bridge.naoqi_client import NaoqiClient
from bridge.playback import HALT_WAIT, LOST_AFTER
from bridge.robot_bridge import RobotBridge
from bridge.serving import Serving, Slot
from bridge.stop_order import STOPPED_BY, StopOrder
from bridge.stopping import STOP_LIMIT, stop_serving
from shared.bus import Bus, Endpoint
from shared.bus.arrival import current_arrival
from shared.bus.deadline import REPLY_MARGIN, Due, current_due
from shared.bus.robot_routes import EXECUTE, STOP
from shared.bus.topics import (
    BRIDGE_FRAMES_TOPIC,
    BRIDGE_OUTCOME_TOPIC,
    BRIDGE_REPORT_TOPIC,
    BRIDGE_STATE_TOPIC,
)
from shared.errors import ArmplanError, RobotBusyError, RobotStateError
from shared.messages import (
    CommandFrames,
    ExecuteReply,
    ExecuteRequest,
    ExecutionOutcome,
    JointState,
    StopReply,
    StopRequest,
)
from shared.messages.stop import MAX_NOTE, read_stop_request
from shared.robot import Side

log = logging.getLogger("armplan.bridge")
#: Longest wait for the stopped execution to end [s]: its next step (a
#: reading, or a check before its movement: the arm's rest, up to a
#: second, and stiffening), then the stop's answer (``HALT_WAIT``).
HALT_END_WAIT = 2.0 * LOST_AFTER + HALT_WAIT + 1.0
#: Longest wait for the stopped arm's measured angles to settle [s].
SETTLE_WAIT = 1.0
#: Two measured readings ``READ_GAP`` apart that differ by no more than
#: this on every joint: the arm is still [rad] (0.06 deg: 1.3 deg/s).
SETTLED = 1e-3

#: Called by a stop with its time [s, monotonic]; drops what waits from
#: before it and returns how many it dropped (the follower's queue).
DropWaiting = Callable[[float], int]


class BridgeService:
    """The robot bridge on a bus.

    Attributes:
        bus: Where it publishes.
        robot: The robot-facing bridge (checks, sends, reads back).
    """

    def __init__(self, bus: Bus, robot: RobotBridge) -> None:
        self.bus = bus
        self.robot = robot
        self._slot = Slot()  # the request being served, and what it has sent
        self._on_halt: list[DropWaiting] = []
        self._lock = threading.Lock()  # guards the four below
        self._orders: list[_Ordered] = []  # stops ordered, not yet answered
        self._last: _Ordered | None = None  # the stops the last reply answered
        self._last_latest = -float("inf")  # [s, monotonic] the last of them
        #: The arm of an execution that ended with an error mid-movement and
        #: has not been read still since: a stop does not say it is still.
        self._unsure: str | None = None

    def on_halt(self, drop: DropWaiting) -> None:
        """Have every ``bridge/stop`` call ``drop`` (the follower's queue)."""
        self._on_halt.append(drop)

    def execute(
        self, request: ExecuteRequest, wait: bool = False, since: float | None = None
    ) -> ExecuteReply:
        """Check, play and report one trajectory (see ``RobotBridge.execute``).

        Args:
            request: The trajectory and how to play it.
            wait: Wait for a trajectory that is playing to end (the
                follower's way), instead of refusing this one.
            since: When the trajectory arrived [s, monotonic] (the
                follower's): a ``bridge/stop`` after that stops it too.
                None: the execute query's arrival
                (:func:`~shared.bus.arrival.current_arrival`): a stop that
                came while it waited in the queue or was checked stops it,
                nothing of it sent.

        Raises:
            RobotBusyError: another trajectory is playing (``wait`` False).
            TrajectoryRefusedError: a frame breaks a limit (nothing sent,
                nothing published).
            CallerDeadlineError: the query's caller would stop waiting
                before the movement ends (nothing of the trajectory sent).
            ServiceUnavailableError: the bridge is stopping (:meth:`stop`):
                nothing sent, or nothing after the approach; or it stopped
                the arm mid-movement, unable to wait for its end.
            RobotStateError: a ``bridge/stop`` stopped it (``stopped``).
            RobotUnavailableError, RobotCommandError: from the robot.
        """
        if since is None:
            since = current_arrival()
        self.robot.refuse_if_stopping("nothing was sent")
        try:  # a trajectory over a limit is refused as such, busy or not
            frames = self.robot.frames(request.trajectory, request.rate)
        except ArmplanError as error:
            log.warning("execute: %s", error.message)
            raise
        order = StopOrder()
        if not self._slot.take(frames.duration, wait, order, since, frames.arm.value):
            # logged once, with the answer (``codec``): a caller's ordinary refusal
            raise RobotBusyError(self.robot.client.url, self._slot.left())
        try:
            reply = self._play(request, frames, order)
        except ArmplanError as error:
            log.warning("execute: %s", error.message)
            serving = self._slot.serving
            if serving is not None and serving.moving:  # it may move on
                with self._lock:
                    self._unsure = frames.arm.value
            order.outcome = ended_by(frames, error)
            self._publish_outcome(order.outcome)
            raise
        else:  # before the slot is free: a stop waiting for it reads it
            order.outcome = ExecutionOutcome(
                outcome="completed", arm=frames.arm.value, duration=frames.duration
            )
            with self._lock:
                if self._unsure == frames.arm.value:  # it played to its end
                    self._unsure = None
        finally:
            self._slot.give_back()
        self._publish_outcome(order.outcome)
        return reply

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
            self._orders.append(_Ordered(at, serving, dropped, reason, notes))
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
        stop = _merged(batch)
        with self._lock:
            self._last = stop
            self._last_latest = max(self._last_latest, *(o.at for o in batch))
        due = current_due()
        if due is not None and due.passed:  # gone, or its clock is behind:
            due = None  # a full answer, for one that still waits
        reply = self._reply(stop, due)
        log.warning("stop: answered %s", reply.to_json())
        return reply

    def _reply(self, stop: _Ordered, due: Due | None) -> StopReply:
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
        an arm whose execution ended with an error mid-movement and was not
        seen still since; with neither, both arms) must settle: two
        readings :data:`READ_GAP` apart within :data:`SETTLED`, read for at
        most :data:`SETTLE_WAIT` (and no longer than the caller's time left
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
            unsure = self._unsure
        arms = {a for a in (arm, unsure) if a is not None} or {"right", "left"}
        names = [n for a in sorted(arms) for n in Side.parse(a).joint_names]
        wait = SETTLE_WAIT
        if due is not None:
            wait = min(wait, due.at - REPLY_MARGIN - time.monotonic())
        if wait <= READ_GAP:
            return False, "no time was left to read the arm settled"
        problem = _settled(self.robot.client, names, wait)
        if problem:
            log.warning("stop: the arm is not known still: %s", problem)
            return False, problem
        with self._lock:
            if self._unsure in arms:
                self._unsure = None
        return True, ""

    def _play(
        self, request: ExecuteRequest, frames: CommandFrames, order: StopOrder
    ) -> ExecuteReply:
        due = current_due()  # the query's caller's; None for the follower
        reply = self.robot.handle(
            request,
            on_state=self._publish_state,
            on_play=self._publish_frames,
            until=None if due is None else due.at - REPLY_MARGIN,
            on_approach=self._slot.approaching,
            on_arrival=self._slot.arrived,
            frames=frames,
            stop=order,
        )
        self.bus.publish(BRIDGE_REPORT_TOPIC, reply.report)
        worst = max(reply.report.tracking_rms_deg.values(), default=0.0)
        log.info("played; worst joint RMS %.3f deg", worst)
        return reply

    def _publish_frames(self, frames: CommandFrames) -> None:
        """Publish and log the frames about to be sent (every check passed).

        The trajectory ends its own length after its call reaches the
        robot: the end a refused caller is told, and a stop waits for, is
        counted from now until then (:mod:`bridge.serving`).
        """
        self._slot.sending()
        self.bus.publish(BRIDGE_FRAMES_TOPIC, frames)
        log.info(
            "playing %d frames (%.2f s, %s arm) on %s",
            len(frames.times),
            frames.duration,
            frames.arm.value,
            self.robot.client.url,
        )

    def stop(self, limit: float = STOP_LIMIT) -> bool:
        """Send no new command; wait for the request being served to end.

        Its approach may end, but its trajectory is not sent: it is answered
        with "the bridge is stopping". A trajectory already playing is
        watched to its end and answered as usual, for at most ``limit`` [s];
        past that the arm is stopped and the request answered with "the
        bridge is stopping; it stopped the arm at about t = X s of Y s ..."
        (:func:`~bridge.stopping.stop_serving`).

        Returns:
            Whether no request is being served any more.
        """
        return stop_serving(self.robot, self._slot, limit)

    def _publish_outcome(self, outcome: ExecutionOutcome) -> None:
        """Publish how an execution ended; nothing once the bus has closed."""
        try:
            self.bus.publish(BRIDGE_OUTCOME_TOPIC, outcome)
        except zenoh.ZError as error:
            log.debug("outcome not published: %s", error)

    def _publish_state(self, state: JointState) -> None:
        """Publish a measured state; none once the bus has closed.

        (A stop that left a trajectory playing: its readings go on.)
        """
        try:
            self.bus.publish(BRIDGE_STATE_TOPIC, state)
        except zenoh.ZError as error:
            log.debug("state not published: %s", error)

    def endpoints(self) -> Sequence[Endpoint[Any, Any]]:
        """The bridge's endpoints: ``bridge/execute`` and ``bridge/stop``.

        The stop has a worker of its own: it is answered while execute
        queries block every other worker.
        """
        return [
            Endpoint(EXECUTE, self.execute),
            Endpoint(
                STOP,
                self.answer_stop,
                own_worker=True,
                at_once=self.order_stop,
                parse=_stop_request,
            ),
        ]


@dataclass(frozen=True)
class _Ordered:
    """Stops ordered together (:meth:`BridgeService.order_stop`).

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


def _merged(batch: list[_Ordered]) -> _Ordered:
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
    return _Ordered(
        first.at,
        serving,
        sum(o.dropped for o in batch),
        next((o.reason for o in batch if o.reason is not None), None),
        notes,
    )


def _another(now: Serving | None, stopped: Serving | None) -> bool:
    """Whether ``now`` is an execution other than ``stopped``, not ordered stopped."""
    if now is None or now.order.ordered:
        return False
    return stopped is None or now.order is not stopped.order


def _stop_request(data: bytes) -> StopRequest:
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


def _settled(client: NaoqiClient, names: list[str], wait: float) -> str:
    """Why ``names``' measured angles were not read settled within ``wait`` [s].

    "" if they were. The reads run on a thread of their own, so that a
    robot that does not answer (a call's timeout, a connection's) takes no
    more than ``wait`` from the reply.
    """
    result: list[str] = []

    def read() -> None:
        try:
            until_still(
                client,
                names,
                use_sensors=True,
                tolerance=SETTLED,
                wait=wait,
                gap=READ_GAP,
                moving="its measured angles did not settle after the stop",
            )
            result.append("")
        except ArmplanError as error:
            result.append(error.message)
        except Exception as error:  # a reply is owed whatever happens
            result.append(f"{type(error).__name__}: {error}")

    reader = threading.Thread(target=read, name="stop-settle", daemon=True)
    reader.start()
    reader.join(wait)
    if not result:
        return f"the robot's angles were not read settled within {wait:.2f} s"
    return result[0]


def ended_by(frames: CommandFrames, error: ArmplanError) -> ExecutionOutcome:
    """The outcome of playing ``frames`` that ended with ``error``.

    ``"stopped"`` if the robot stopped the movement or released the arm
    (``RobotStateError.stopped``), with where if known; else ``"error"``.
    """
    stopped = isinstance(error, RobotStateError) and error.stopped
    evidence = error.evidence if stopped else {}
    return ExecutionOutcome(
        outcome="stopped" if stopped else "error",
        arm=frames.arm.value,
        duration=frames.duration,
        error_kind=error.kind,
        message=error.message,
        phase=evidence.get("phase"),
        played=evidence.get("played"),
        phase_duration=evidence.get("duration"),
        stopped_by=evidence.get("stopped_by"),
        stop_reason=evidence.get("stop_reason"),
    )
