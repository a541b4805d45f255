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

``<ns>/bridge/stop``, the operator's stop over Zenoh, is answered by
:class:`~bridge.stop_desk.StopDesk` (see :mod:`bridge.stop_desk`): ANY query
on it stops the execution being served, at once; the reply waits for its end.

Run it with ``python -m bridge.serve --robot URL`` (``armplan up
--with-sim`` and ``armplan demo`` do); see :mod:`bridge.serve`.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from functools import partial
from typing import Any

import zenoh

from bridge.robot_bridge import RobotBridge
from bridge.serving import Slot
from bridge.stop_desk import DropWaiting, StopDesk, stop_request
from bridge.stop_order import StopOrder
from bridge.stopping import STOP_LIMIT, stop_serving
from shared.bus import Bus, Endpoint
from shared.bus.arrival import current_arrival
from shared.bus.deadline import REPLY_MARGIN, current_due
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
from shared.text.counted import counted

log = logging.getLogger("armplan.bridge")


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
        self._desk = StopDesk(bus, robot, self._slot)  # bridge/stop's answers
        bus.caller_gone(None)  # watch callers' sessions end from the start

    def on_halt(self, drop: DropWaiting) -> None:
        """Have every ``bridge/stop`` call ``drop`` (the follower's queue)."""
        self._desk.on_halt(drop)

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
                self._desk.mark_unsure(frames.arm.value)
            order.outcome = ended_by(frames, error)
            raise
        else:  # before the slot is free: a stop waiting for it reads it
            order.outcome = ExecutionOutcome(
                outcome="completed", arm=frames.arm.value, duration=frames.duration
            )
            self._desk.mark_sure(frames.arm.value)  # it played to its end
        finally:
            self._slot.give_back()
            # once free: the put may wait up to 5 s (BLOCK), and a stop's
            # reply waits for the slot, not for the bus
            if order.outcome is not None:
                self._publish_outcome(order.outcome)
        return reply

    def order_stop(self, payload: bytes) -> None:
        """Order the stop a ``bridge/stop`` query asks, as it arrives.

        On Zenoh's thread, whatever the payload or deadline
        (:meth:`StopDesk.order_stop <bridge.stop_desk.StopDesk.order_stop>`).
        """
        self._desk.order_stop(payload)

    def halt(self, request: StopRequest) -> StopReply:
        """Stop the execution being served, drop what waits; say if still.

        :meth:`order_stop` with ``request``'s reason, then
        :meth:`answer_stop` (:meth:`~bridge.stop_desk.StopDesk.halt`).
        """
        return self._desk.halt(request)

    def answer_stop(self, request: StopRequest) -> StopReply:
        """The reply to the ``bridge/stop`` queries ordered since the last one.

        Once the stopped execution has ended, whether the arm is known
        still (:meth:`StopDesk.answer_stop
        <bridge.stop_desk.StopDesk.answer_stop>`).
        """
        return self._desk.answer_stop(request)

    def _play(
        self, request: ExecuteRequest, frames: CommandFrames, order: StopOrder
    ) -> ExecuteReply:
        due = current_due()  # the query's caller's; None for the follower
        caller = None if due is None else due.session
        reply = self.robot.handle(
            request,
            on_state=self._publish_state,
            on_play=self._publish_frames,
            until=None if due is None else due.at - REPLY_MARGIN,
            on_approach=partial(self._approaching, frames),
            on_arrival=self._slot.arrived,
            frames=frames,
            stop=order,
            gone=None if caller is None else partial(self.bus.caller_gone, caller),
        )
        self.bus.publish(BRIDGE_REPORT_TOPIC, reply.report)
        worst = max(reply.report.tracking_rms_deg.values(), default=0.0)
        log.info("played; worst joint RMS %.3f deg", worst)
        return reply

    def _approaching(self, frames: CommandFrames, approach: float) -> None:
        """Mark and log the approach, ``approach`` [s] long, about to be sent.

        The arm moves from where it is to ``frames``' start before they
        play: the log says so, or an operator sees it move unannounced.
        """
        self._slot.approaching(approach)
        log.info(
            "approaching the trajectory's start (%.2f s, %s arm) on %s",
            approach,
            frames.arm.value,
            self.robot.client.url,
        )

    def _publish_frames(self, frames: CommandFrames) -> None:
        """Publish and log the frames about to be sent (every check passed).

        The trajectory ends its own length after its call reaches the
        robot: the end a refused caller is told, and a stop waits for, is
        counted from now until then (:mod:`bridge.serving`).
        """
        self._slot.sending()
        self.bus.publish(BRIDGE_FRAMES_TOPIC, frames)
        log.info(
            "playing %s (%.2f s, %s arm) on %s",
            counted(len(frames.times), "frame"),
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
                parse=stop_request,
            ),
        ]


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
