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

``<ns>/bridge/stop`` (:meth:`BridgeService.halt`) is the operator's stop
over Zenoh: the execution being served is ordered stopped
(``bridge.stop_order``; a movement playing has its arm's motion tasks
killed at once, ``ALMotion.killTasksUsingResources``), its caller gets the
robot's usual "stopped" error, ``bridge/outcome`` says ``"stopped"`` (by
``bridge/stop``), the follower's waiting trajectories are dropped, and the
:class:`~shared.messages.StopReply` comes once the arm is still. It has a
worker of its own (``Endpoint.own_worker``): never queued behind an
execute query. A stop is not a latch: an execute query after it plays.

Run it with ``python -m bridge.serve --robot URL`` (``armplan up
--with-sim`` and ``armplan demo`` do); see :mod:`bridge.serve`.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from typing import Any

import zenoh

from bridge.at_rest import READ_GAP, until_still
from bridge.playback import HALT_WAIT, LOST_AFTER
from bridge.robot_bridge import RobotBridge
from bridge.serving import Slot
from bridge.stop_order import StopOrder
from bridge.stopping import STOP_LIMIT, stop_serving
from shared.bus import Bus, Endpoint
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
        self.robot.refuse_if_stopping("nothing was sent")
        try:  # a trajectory over a limit is refused as such, busy or not
            frames = self.robot.frames(request.trajectory, request.rate)
        except ArmplanError as error:
            log.warning("execute: %s", error.message)
            raise
        order = StopOrder()
        if not self._slot.take(frames.duration, wait, order, since):
            remaining = self._slot.left()
            log.warning("execute: refused, the robot is busy (%.1f s left)", remaining)
            raise RobotBusyError(self.robot.client.url, remaining)
        try:
            reply = self._play(request, frames, order)
        except ArmplanError as error:
            log.warning("execute: %s", error.message)
            order.outcome = ended_by(frames, error)
            self._publish_outcome(order.outcome)
            raise
        else:  # before the slot is free: a stop waiting for it reads it
            order.outcome = ExecutionOutcome(
                outcome="completed", arm=frames.arm.value, duration=frames.duration
            )
        finally:
            self._slot.give_back()
        self._publish_outcome(order.outcome)
        return reply

    def halt(self, request: StopRequest) -> StopReply:
        """Stop the execution being served, drop what waits; answer once still.

        The execution being served (if any) is ordered stopped: a movement
        playing has its arm's motion tasks killed at once
        (``killTasksUsingResources``, again until its call has ended), one
        not sent yet is not sent; its caller gets the robot's "stopped"
        error (``robot_state``) and ``bridge/outcome`` says ``"stopped"``
        by ``bridge/stop``. The follower's waiting trajectories that
        arrived before the stop are dropped. The answer comes once that
        execution has ended (at most :data:`HALT_END_WAIT`) and the arm's
        measured angles have settled (at most :data:`SETTLE_WAIT`); with
        nothing served, at once. Idempotent; not a latch: the next
        execute query plays.
        """
        at = time.monotonic()
        why = "" if request.reason is None else f' (reason: "{request.reason}")'
        dropped = sum(drop(at) for drop in self._on_halt)
        serving = self._slot.halt(request.reason, at)
        log.warning(
            "stop: asked on %s%s; %s; %d waiting trajectories dropped",
            self.bus.key(STOP.path),
            why,
            "nothing was being played"
            if serving is None
            else "stopping the movement playing"
            if serving.moving
            else "stopping the execution before its movement",
            dropped,
        )
        if serving is None:
            return StopReply(
                playing=False,
                stopped=False,
                dropped=dropped,
                waited=time.monotonic() - at,
                reason=request.reason,
            )
        due = current_due()
        give_up = at + HALT_END_WAIT
        if due is not None:
            give_up = min(give_up, due.at - REPLY_MARGIN - SETTLE_WAIT)
        left = self._slot.wait_free(lambda _serving, _now: give_up)
        outcome = serving.order.outcome
        ended = left is None or left.order is not serving.order
        stopped = (
            outcome is not None
            and outcome.outcome == "stopped"
            and outcome.stopped_by is not None
        )
        still = ended and self._settled(outcome, due)
        if not ended:
            log.warning(
                "stop: the execution had not ended %.1f s after the stop; "
                "answering without waiting for it",
                time.monotonic() - at,
            )
        reply = StopReply(
            playing=serving.moving,
            stopped=stopped,
            arm=None if outcome is None else outcome.arm,
            phase=outcome.phase if stopped and outcome is not None else None,
            played=outcome.played if stopped and outcome is not None else None,
            phase_duration=outcome.phase_duration
            if stopped and outcome is not None
            else None,
            dropped=dropped,
            still=still,
            waited=time.monotonic() - at,
            reason=request.reason,
        )
        log.warning("stop: answered %s", reply.to_json())
        return reply

    def _settled(self, outcome: ExecutionOutcome | None, due: Any) -> bool:
        """Whether the arm of ``outcome`` holds still (its measured angles)."""
        if outcome is None:
            return True
        wait = SETTLE_WAIT
        if due is not None:
            wait = min(wait, max(due.at - REPLY_MARGIN - time.monotonic(), 0.0))
        names = list(Side.parse(outcome.arm).joint_names)
        try:
            until_still(
                self.robot.client,
                names,
                use_sensors=True,
                tolerance=SETTLED,
                wait=wait,
                gap=READ_GAP,
                moving="its measured angles did not settle after the stop",
            )
        except ArmplanError as error:
            log.warning("stop: the arm is not known still: %s", error.message)
            return False
        return True

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
            Endpoint(STOP, self.halt, own_worker=True),
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
