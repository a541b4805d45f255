"""A count of one reads in the singular in what the commands print.

A lab user saw ``sent 1 of 1 messages`` and ``1 messages on 1 channels``.
Real MCAP files, a real router on a free loopback port, the real commands
as processes: one recorded message is ``1 message on 1 channel``, a replay
of it ``sent 1 of 1 message``, and a recording of it ``1 message in``.
"""

from __future__ import annotations

import subprocess
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from armplan_cli import armplan
from record_cli import record_command

from armplan.launch import free_endpoint
from shared.bus import Bus, BusConfig, open_router
from shared.recording import MessageWriter
from shared.recording.inventory import take_inventory
from shared.recording.raw_payload import JSON_SCHEMA

NAMESPACE = "singulartest"
#: Longest wait for a subscriber to match, or a message to arrive [s].
WAIT = 20.0


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


@pytest.fixture
def one_message(tmp_path: Path) -> Path:
    """An MCAP file holding one JSON message on one channel, misc/one."""
    path = tmp_path / "one.mcap"
    with MessageWriter(path, chunked=False) as writer:
        channel = writer.add_channel("misc/one", "json", JSON_SCHEMA)
        writer.write_raw(channel, b'{"i": 0}', 10**18)
    return path


def test_inspect_says_one_message_on_one_channel(one_message: Path) -> None:
    """``armplan inspect``'s first line: "1 message on 1 channel"."""
    out = armplan("inspect", str(one_message))
    assert out.returncode == 0, out.stderr
    assert f"{one_message}: 1 message on 1 channel, namespace -" in out.stdout, (
        out.stdout
    )


def test_replay_says_it_sent_one_of_one_message(
    config: BusConfig, one_message: Path
) -> None:
    """``armplan replay`` of it to a real router: "sent 1 of 1 message in"."""
    got: list[bytes] = []
    arrived = threading.Event()

    def on_sample(sample: zenoh.Sample) -> None:
        got.append(sample.payload.to_bytes())
        arrived.set()

    with Bus.connect(config) as bus:
        subscriber = bus.session.declare_subscriber(bus.key("misc/one"), on_sample)
        out = armplan(
            "replay",
            str(one_message),
            "--connect",
            config.endpoint,
            "--namespace",
            NAMESPACE,
        )
        arrived.wait(WAIT)
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert out.returncode == 0, out.stderr
    assert got == [b'{"i": 0}']
    assert "armplan replay: sent 1 of 1 message in " in out.stdout, out.stdout


def test_record_of_one_message_says_one_message(
    config: BusConfig, tmp_path: Path
) -> None:
    """``armplan record``'s last line for one put: "1 message in <file>"."""
    out = tmp_path / "s.mcap"
    command = record_command(config, out, "--no-foxglove", "--duration", "3")
    with (
        subprocess.Popen(
            command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        ) as process,
        Bus.connect(config) as bus,
    ):
        publisher = bus.session.declare_publisher(
            bus.key("misc/x"), congestion_control=zenoh.CongestionControl.BLOCK
        )
        deadline = time.monotonic() + WAIT
        while not publisher.matching_status.matching:
            assert time.monotonic() < deadline, "the recorder never subscribed"
            assert process.poll() is None, process.communicate()
            time.sleep(0.01)
        publisher.put(b'{"i": 1}')
        publisher.undeclare()  # type: ignore[no-untyped-call]
        stdout, stderr = process.communicate(timeout=60)
    assert process.returncode == 0, stderr
    assert take_inventory(out).count == 1
    assert f"armplan record: 1 message in {out}\n" in stdout, stdout
