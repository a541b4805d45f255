"""Play every trajectory the planner publishes (``bridge --follow``).

The planner puts each finished trajectory on ``<ns>/plan/trajectory``; a
follower subscribed there hands each one to the bridge, in arrival order, on
its own thread (Zenoh's threads only queue). So a recording replayed with
``armplan replay --keys plan/trajectory`` drives the robot. A payload that is
not a trajectory, a refused trajectory or a lost robot is logged, and the
follower goes on with the next one. A movement the robot stopped (its
motion task killed: ``killTasksUsingResources``, ``killAll``, a rest, the
fall manager; or its arm released) is an operator's stop: every trajectory
that arrived before the bridge saw the stop is dropped (and the count
logged), so the arm stays still; the next trajectory published plays.
A ``bridge/stop`` query does the same at once, whether a movement plays
or not (``BridgeService.halt`` calls :meth:`TrajectoryFollower.drop_waiting`
and answers with the count); a trajectory the worker had taken but not yet
started is stopped as it starts (``since``).
When more trajectories wait than ``QUEUE_LIMIT``, the oldest waiting one is
dropped (with a warning): the robot falls behind by at most that many, and
the newest command is kept. A payload larger than the bus's ``max_payload``
is dropped unread as it arrives (with a warning), as ``bridge/execute``
refuses it ``payload_too_large``: one 204 MB publication held 2.7 GB of the
bridge's memory while it was parsed, and sixteen could wait.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from typing import TypeVar

import zenoh

from bridge.service import BridgeService
from bridge.stop_order import STOPPED_BY
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.errors import ArmplanError, RobotStateError
from shared.messages import ExecuteRequest, Trajectory, parse

log = logging.getLogger("armplan.bridge")
#: Trajectories waiting to be played; beyond it the oldest waiting is dropped.
QUEUE_LIMIT = 16
#: Longest wait for the trajectory being played when stopping [s].
STOP_GRACE = 2.0


_Item = TypeVar("_Item")


def offer_newest(waiting: queue.Queue[_Item], item: _Item) -> bool:
    """Queue ``item``; if ``waiting`` is full, drop its oldest item first.

    Returns:
        Whether an item was dropped.
    """
    dropped = False
    while True:
        try:
            waiting.put_nowait(item)
            return dropped
        except queue.Full:
            try:
                waiting.get_nowait()
                dropped = True
            except queue.Empty:  # the worker took one meanwhile
                pass


class TrajectoryFollower:
    """Plays the trajectories published on ``plan/trajectory`` through a bridge.

    Attributes:
        bridge: The bridge service that plays them.
        rate: Frame rate of the command frames [Hz].
        played: Number of trajectories played to the end.
        dropped: Number of waiting trajectories dropped because the robot
            stopped a movement before they arrived.
    """

    def __init__(self, bridge: BridgeService, rate: float = 25.0) -> None:
        self.bridge = bridge
        self.rate = rate
        self.played = 0
        self.dropped = 0
        # (arrival [s, monotonic], payload); None: stop the worker
        self._queue: queue.Queue[tuple[float, bytes] | None] = queue.Queue(QUEUE_LIMIT)
        self._thread = threading.Thread(
            target=self._work, name="bridge-follower", daemon=True
        )
        self._subscriber: zenoh.Subscriber[None] | None = None

    def start(self) -> TrajectoryFollower:
        """Start playing, then subscribe."""
        self._thread.start()
        self.bridge.on_halt(self.drop_waiting)
        bus = self.bridge.bus
        key = bus.key(TRAJECTORY_TOPIC)
        self._subscriber = bus.session.declare_subscriber(key, self._on_sample)
        log.info("following trajectories on %s", key)
        return self

    def _on_sample(self, sample: zenoh.Sample) -> None:  # Zenoh's thread
        size, limit = len(sample.payload), self.bridge.bus.config.max_payload
        if size > limit:  # sized before copying: never read
            log.warning(
                "follow: dropped a payload of %d bytes on %s, over the bus's "
                "max_payload of %d bytes (not played)",
                size,
                sample.key_expr,
                limit,
            )
            return
        item = (time.monotonic(), sample.payload.to_bytes())
        if offer_newest(self._queue, item):
            log.warning(
                "follow: %d trajectories waiting; dropped the oldest of them",
                QUEUE_LIMIT,
            )

    def _work(self) -> None:
        while (item := self._queue.get()) is not None:
            try:
                self._play(*item)
            except RobotStateError as error:  # the bridge has logged it
                by_query = error.evidence.get("stopped_by") == STOPPED_BY
                if error.stopped and not by_query:  # the query dropped them
                    self._drop_before(error.stopped_at or time.monotonic())
            except ArmplanError:  # the bridge has logged it
                pass
            except Exception:  # the follower never dies
                log.exception("follow: failed to play a trajectory")

    def drop_waiting(self, stopped_at: float) -> int:
        """Drop the waiting trajectories that arrived before ``stopped_at``.

        What was queued before a stop must not move the arm again; what
        arrived since was published knowing of the stop, and plays.

        Returns:
            How many were dropped.
        """
        with self._queue.mutex:  # Zenoh's thread may be queueing meanwhile
            waiting = self._queue.queue
            kept = [i for i in waiting if i is None or i[0] > stopped_at]
            gone = len(waiting) - len(kept)
            waiting.clear()
            waiting.extend(kept)
            self._queue.not_full.notify_all()
        self.dropped += gone
        return gone

    def _drop_before(self, stopped_at: float) -> None:
        """Drop what waits from before the robot's stop at ``stopped_at``.

        The robot stopped the movement (an operator's stop through NAOqi):
        :meth:`drop_waiting`, and say so.
        """
        gone = self.drop_waiting(stopped_at)
        log.warning(
            "follow: the robot stopped the movement; dropped the %d "
            "trajectories waiting from before the stop (the arm stays still); "
            "the next trajectory published on %s will play",
            gone,
            self.bridge.bus.key(TRAJECTORY_TOPIC),
        )

    def _play(self, arrival: float, payload: bytes) -> None:
        try:
            trajectory = parse(Trajectory, payload)
        except ArmplanError as error:
            log.warning("follow: not a trajectory: %s", error.message)
            return
        self.bridge.execute(
            ExecuteRequest(trajectory=trajectory, rate=self.rate),
            wait=True,
            since=arrival,
        )
        self.played += 1

    def stop(self) -> None:
        """Unsubscribe; finish (at most ``STOP_GRACE`` s of) the current one."""
        if self._subscriber is not None:
            self._subscriber.undeclare()  # type: ignore[no-untyped-call]
            self._subscriber = None
        while True:  # drop what waits, then wake the worker
            try:
                self._queue.get_nowait()
            except queue.Empty:
                break
        self._queue.put(None)
        self._thread.join(STOP_GRACE)
