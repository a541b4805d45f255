"""Publications keep a burst whole (Zenoh ``BLOCK``), except ``bridge/state``.

A real router, a publishing :class:`~shared.bus.Bus` and a subscriber whose
callback is slow (a recorder writing, a follower checking): with Zenoh's
default ``DROP`` congestion control, 40 trajectories of 5 MB put at once
arrived 35 (``Bus.publish`` used it for every topic). The congestion
control each publication carries is read on the subscriber's side.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator

import numpy as np
import pytest
import zenoh
from conftest import moving_trajectory

from armplan.launch.ports import free_endpoint
from shared.bus import Bus
from shared.bus.config_file import load_config
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.bus.session import open_client, open_router
from shared.bus.topics import BRIDGE_STATE_TOPIC, TOPICS, droppable
from shared.messages.frames import JointState
from shared.robot import Side

#: Trajectories in the burst, and samples in each (~380 bytes a sample).
BURST, SAMPLES = 40, 13_000
#: How long the subscriber's callback takes for each [s].
SLOW = 0.05


class Heard:
    """What a slow subscriber received: payload sizes and congestion controls."""

    def __init__(self) -> None:
        self.sizes: list[int] = []
        self.controls: list[zenoh.CongestionControl] = []
        self.lock = threading.Lock()

    def __call__(self, sample: zenoh.Sample) -> None:
        with self.lock:
            self.sizes.append(len(sample.payload.to_bytes()))
            self.controls.append(sample.congestion_control)
        time.sleep(SLOW)

    def wait(self, count: int, timeout: float) -> int:
        """Wait until ``count`` arrived or ``timeout`` [s] passed; how many did."""
        end = time.monotonic() + timeout
        while time.monotonic() < end and len(self.sizes) < count:
            time.sleep(0.05)
        time.sleep(0.5)  # nothing more arrives than was sent
        return len(self.sizes)


@pytest.fixture
def wire() -> Iterator[tuple[Bus, zenoh.Session]]:
    """A router, a Bus that publishes and a plain session that subscribes."""
    config = load_config(endpoints=(free_endpoint(),))
    router = open_router(config)
    try:
        listener = open_client(config)
        try:
            with Bus.connect(config) as bus:
                yield bus, listener
        finally:
            listener.close()
    finally:
        router.close()


def test_a_burst_of_large_trajectories_reaches_a_slow_subscriber_whole(
    wire: tuple[Bus, zenoh.Session],
) -> None:
    """40 trajectories of ~5 MB put at once all arrive, in full."""
    bus, listener = wire
    heard = Heard()
    trajectory = moving_trajectory(SAMPLES, np.random.default_rng(7))
    size = len(trajectory.to_json())
    assert size > 4_000_000
    subscriber = listener.declare_subscriber(bus.key(TRAJECTORY_TOPIC), heard)
    try:
        time.sleep(0.5)  # the subscription reaches the router
        for _ in range(BURST):
            bus.publish(TRAJECTORY_TOPIC, trajectory)
        arrived = heard.wait(BURST, timeout=BURST * SLOW + 30.0)
    finally:
        subscriber.undeclare()
    assert arrived == BURST, f"{arrived} of {BURST} arrived"
    assert set(heard.sizes) == {size}
    assert all(c == zenoh.CongestionControl.BLOCK for c in heard.controls)


def test_only_the_joint_state_stream_may_be_dropped(
    wire: tuple[Bus, zenoh.Session],
) -> None:
    """``bridge/state`` arrives marked DROP (its 50 Hz publisher never
    waits); the table marks it alone, and an unknown path is kept."""
    bus, listener = wire
    heard = Heard()
    subscriber = listener.declare_subscriber(bus.key(BRIDGE_STATE_TOPIC), heard)
    try:
        time.sleep(0.5)
        names = list(Side.RIGHT.joint_names)
        bus.publish(
            BRIDGE_STATE_TOPIC,
            JointState(time=0.0, joint_names=names, positions=[0.0] * len(names)),
        )
        assert heard.wait(1, timeout=10.0) == 1
    finally:
        subscriber.undeclare()
    assert heard.controls == [zenoh.CongestionControl.DROP]
    assert [t.path for t in TOPICS if t.droppable] == [BRIDGE_STATE_TOPIC]
    assert not droppable("misc/unknown")
