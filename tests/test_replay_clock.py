"""A publisher whose clock is off: replay keeps the real spacing, inspect warns.

The log time of a message is its Zenoh timestamp, the publisher's own when
it sets one. One put stamped 20 s in the past, then five normal ones 0.1 s
apart, were a 20.5 s session to ``inspect`` and took ``armplan replay``
21.6 s; a file in reverse log-time order went out at once reported as up to
50 ms "late". Real router, real recorder, real MCAP files and processes.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest
import zenoh
from armplan_cli import armplan

from armplan.launch import free_endpoint
from services.recorder import RecorderOptions
from services.recorder.replay import replay, replay_items
from services.recorder.service import Recorder
from shared.bus import Bus, BusConfig, open_router
from shared.recording.inventory import take_inventory
from shared.recording.writer import MessageWriter

NS = "replayclock"
#: How far behind the odd publisher's clock is [s].
BEHIND = 20.0
#: Gap between the normal puts [s].
GAP = 0.1


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NS)
    with open_router(config):
        yield config


@pytest.fixture(scope="module")
def skewed(config: BusConfig, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A recording: one put stamped ``BEHIND`` s ago, then five 0.1 s apart."""
    out = tmp_path_factory.mktemp("clock") / "skewed.mcap"
    options = RecorderOptions(output=out, keys=("misc/*",), foxglove=False)
    with Bus.connect(config) as bus, Recorder(bus, options):
        session = bus.session
        past = datetime.now(UTC) - timedelta(seconds=BEHIND)
        stamp = zenoh.Timestamp(past, session.new_timestamp().get_id())
        session.put(bus.key("misc/a"), b'{"i": 0}', timestamp=stamp)
        for i in range(1, 6):
            time.sleep(GAP)
            session.put(bus.key("misc/a"), json.dumps({"i": i}).encode())
        time.sleep(0.5)
    return out


def test_replay_keeps_the_spacing_the_recorder_saw(skewed: Path) -> None:
    """Offsets from the receipt times: 0 to about 0.5 s, never 20.5 s."""
    offsets = [item.offset for item in replay_items(skewed)]
    assert len(offsets) == 6
    assert offsets == sorted(offsets)
    assert offsets[0] == 0.0
    assert 4 * GAP < offsets[-1] < 5 * GAP + 0.4, offsets


def test_armplan_replay_of_it_takes_the_session_s_time(
    config: BusConfig, skewed: Path
) -> None:
    """`armplan replay` sends the 6 messages in about 0.5 s (it took 21.6)."""
    began = time.monotonic()
    out = armplan("replay", str(skewed), "--connect", config.endpoint)
    took = time.monotonic() - began
    assert out.returncode == 0, out.stderr
    assert "sent 6 of 6 messages in 0." in out.stdout, out.stdout
    assert took < 10.0


def test_inspect_warns_of_a_publisher_s_clock(skewed: Path) -> None:
    """`armplan inspect` names the topic and how far the clock may be off."""
    out = armplan("inspect", str(skewed))
    assert out.returncode == 0, out.stderr
    text = " ".join(out.stdout.split())
    assert "warning: log time and publish (receipt) time differ by up to 20." in text, (
        text
    )
    assert f"(on {NS}/misc/a): a publisher's clock may be off by 20." in text
    assert "(behind)" in text
    offset = take_inventory(skewed).clock_offset
    assert offset is not None and -BEHIND - 1.0 < offset < -BEHIND + 1.0


def test_a_recording_on_time_has_no_warning(config: BusConfig, tmp_path: Path) -> None:
    """Normal puts (the router stamps them): no clock warning, offset null."""
    out = tmp_path / "fine.mcap"
    options = RecorderOptions(output=out, keys=("misc/*",))
    with Bus.connect(config) as bus, Recorder(bus, options):
        for i in range(3):
            bus.session.put(bus.key("misc/a"), json.dumps({"i": i}).encode())
            time.sleep(GAP)
        time.sleep(0.5)
    assert take_inventory(out).clock_offset is None
    said = armplan("inspect", str(out))
    assert said.returncode == 0, said.stderr
    assert "warning" not in said.stdout


def reversed_file(path: Path, n: int = 50) -> Path:
    """Another tool's file: ``n`` messages, log times 10 ms apart, descending."""
    base = 1_700_000_000 * 10**9
    with MessageWriter(path, chunked=False) as writer:
        channel = writer.channel_id("armplan/misc/a", "json", {"type": "object"})
        for i in range(n):
            when = base + (n - 1 - i) * 10**7
            writer.write_raw(channel, b'{"i": %d}' % i, when, when)
    return path


def test_a_file_in_reverse_log_time_order_is_sent_in_order_none_late(
    tmp_path: Path,
) -> None:
    """Each offset at least the one before's (all 0 here), and a replay at
    speed 10 reports no lateness it did not have (it said 50.2 ms)."""
    items = replay_items(reversed_file(tmp_path / "rev.mcap"))
    assert [item.offset for item in items] == [0.0] * 50
    sent: list[bytes] = []
    stats = replay(items, lambda path, data, enc: sent.append(data), speed=10.0)
    assert sent == [b'{"i": %d}' % i for i in range(50)]
    assert stats.sent == 50
    assert 0.0 <= stats.late < 0.02, stats


def test_another_tools_file_in_order_keeps_its_log_time_spacing(
    tmp_path: Path,
) -> None:
    """Without the recorder's metadata the log times space the messages
    (the publish times another tool writes may mean nothing): 0, 0.1, 0.2 s."""
    path = tmp_path / "other.mcap"
    with MessageWriter(path, chunked=False) as writer:
        channel = writer.channel_id("misc/a", "json", {"type": "object"})
        for i in range(3):
            writer.write_raw(channel, b'{"i": %d}' % i, (10 + i) * 10**8, 1)
    offsets = [item.offset for item in replay_items(path)]
    assert offsets == pytest.approx([0.0, 0.1, 0.2])
