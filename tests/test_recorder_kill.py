"""A recorder killed with SIGKILL loses at most the last second of messages.

A publisher sends at a known rate; the recorder process is killed with
SIGKILL mid-stream. The file, read with ``recover``, must hold an in-order
prefix of what was sent that includes every message sent more than 1 s
before the kill (the recorder flushes at least every 0.2 s, so in practice
it loses about that much).
"""

from __future__ import annotations

import json
import os
import signal
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh

from armplan.launch import free_endpoint
from services.recorder import RecorderProcess
from shared.bus import Bus, BusConfig, open_router
from shared.errors import RecordingError
from shared.recording import read_records

NAMESPACE = "killtest"
#: Loss allowed on SIGKILL [s].
MAX_LOSS = 1.0


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


def stream_and_kill(
    config: BusConfig, recorder: RecorderProcess, rate: float, before_kill: float
) -> tuple[list[int], int]:
    """Publish {"i": i} at ``rate`` [Hz]; SIGKILL the recorder after ``before_kill``
    [s]. Returns the send time of each message [ns] and the kill time [ns]."""
    sent: list[int] = []
    period = 1.0 / rate
    with Bus.connect(config) as bus:
        start = time.monotonic()
        while time.monotonic() - start < before_kill:
            due = start + len(sent) * period
            time.sleep(max(0.0, due - time.monotonic()))
            sent.append(time.time_ns())
            bus.session.put(
                bus.key("stream/data"),
                json.dumps({"i": len(sent) - 1}).encode(),
                congestion_control=zenoh.CongestionControl.BLOCK,
            )
        killed = time.time_ns()
        os.killpg(recorder.pid, signal.SIGKILL)
        recorder.process.wait(30)
    return sent, killed


@pytest.mark.parametrize("rate", [50.0, 500.0])
def test_sigkill_loses_at_most_the_last_second(
    config: BusConfig, tmp_path: Path, rate: float
) -> None:
    """An in-order prefix survives, holding everything sent 1 s before the kill."""
    out = tmp_path / "killed.mcap"
    recorder = RecorderProcess.start(config, out, keys=["stream/*"])
    try:
        sent, killed = stream_and_kill(config, recorder, rate, before_kill=3.0)
    finally:
        recorder.kill()
    assert recorder.process.returncode == -signal.SIGKILL
    with pytest.raises(RecordingError, match="damaged after"):
        list(read_records(out))  # no summary: a killed writer's file
    got = [r for r in read_records(out, recover=True) if r.topic.endswith("/data")]
    indices = [r.data["i"] for r in got]
    assert indices == list(range(len(indices)))  # an in-order prefix
    must_have = sum(1 for t in sent if t < killed - MAX_LOSS * 1e9)
    lost_s = (killed - got[-1].publish_time) / 1e9
    print(
        f"rate {rate:g} Hz: sent {len(sent)}, recorded {len(got)}, "
        f"lost {len(sent) - len(got)} ({lost_s:.3f} s before the kill)"
    )
    assert len(got) >= must_have
    assert lost_s < MAX_LOSS
