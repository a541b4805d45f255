"""SIGHUP (a closed terminal, a dropped ssh session) stops armplan cleanly.

Left to its default, SIGHUP killed ``armplan record`` at once: the file
had no summary. The commands that run until stopped now stop on it as on
Ctrl-C: ``armplan record`` closes its file whole and exits 0, as it does
on Ctrl-C and SIGTERM; ``armplan demo`` stops every process it started and
exits 129 ("hung up", 128 + SIGHUP), as it exits 130 on Ctrl-C and 143 on
SIGTERM. A command started under ``nohup`` keeps running. The terminal is a
real pseudo-terminal that the test closes: the kernel sends the SIGHUP, and
the command's later writes to it fail.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from mcap.reader import make_reader
from record_cli import record_command

from armplan.launch import free_endpoint
from shared.bus import BusConfig, open_router
from shared.recording import read_records, summarize
from tests.closing_terminal import Terminal
from tests.test_demo import RUN_TIMEOUT, STOP_TIMEOUT, alive, descendants
from tests.test_recorder import publish_all

NS = "hangup"
#: What a recording gets: five messages on one key.
PAYLOADS = [("misc/x", json.dumps({"i": i}).encode()) for i in range(5)]
#: Longest wait for a recorder to exit once told to [s].
EXIT_TIMEOUT = 60.0


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NS)
    with open_router(config):
        yield config


def whole(path: Path) -> list[bytes]:
    """The recorded payloads of ``path``, which must be closed with its summary."""
    with path.open("rb") as stream:
        assert make_reader(stream).get_summary() is not None, "no summary"
    return [r.raw for r in read_records(path) if r.topic == f"{NS}/misc/x"]


ENV = {**os.environ, "ARMPLAN_ZENOH_CONFIG": ""}


def test_record_whose_terminal_closes_closes_its_file_whole(
    config: BusConfig, tmp_path: Path
) -> None:
    """The terminal closes while recording: exit 0, every message in a file
    with its summary (SIGHUP killed it: no summary)."""
    out = tmp_path / "hup.mcap"
    terminal = Terminal(record_command(config, out), env=ENV)
    try:
        terminal.wait_for("Ctrl-C stops", 60.0)
        publish_all(config, PAYLOADS)
        terminal.close()
        assert terminal.process.wait(EXIT_TIMEOUT) == 0
    finally:
        terminal.kill()
    assert whole(out) == [payload for _, payload in PAYLOADS]


def test_record_sighup_is_a_clean_stop_like_sigterm(
    config: BusConfig, tmp_path: Path
) -> None:
    """``kill -HUP``: the same stop as Ctrl-C, the closing line printed."""
    out = tmp_path / "hup.mcap"
    process = subprocess.Popen(
        record_command(config, out),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=ENV,
    )
    try:
        assert process.stdout is not None
        assert "Ctrl-C stops" in process.stdout.readline()
        publish_all(config, PAYLOADS)
        process.send_signal(signal.SIGHUP)
        stdout, stderr = process.communicate(timeout=EXIT_TIMEOUT)
    finally:
        process.kill()
        process.wait(10)
    assert process.returncode == 0, stderr
    assert stdout.startswith("armplan record: 5 messages (and 1 derived for Foxglove)")
    assert len(whole(out)) == 5


def test_record_under_nohup_outlives_its_terminal(
    config: BusConfig, tmp_path: Path
) -> None:
    """Started with SIGHUP ignored (nohup): it records on after the terminal
    closes, and SIGTERM still stops it cleanly."""
    out = tmp_path / "nohup.mcap"
    terminal = Terminal(record_command(config, out), env=ENV, ignore_hangup=True)
    try:
        terminal.wait_for("Ctrl-C stops", 60.0)
        terminal.close()
        publish_all(config, PAYLOADS)  # after the hangup
        assert terminal.process.poll() is None, "the hangup stopped it"
        terminal.process.send_signal(signal.SIGTERM)
        assert terminal.process.wait(EXIT_TIMEOUT) == 0
    finally:
        terminal.kill()
    assert len(whole(out)) == 5


def test_the_recorder_process_stops_whole_on_sighup(
    config: BusConfig, tmp_path: Path
) -> None:
    """``python -m services.recorder`` (what ``armplan demo`` and compose
    run): SIGHUP closes the file with its summary, exit 0."""
    out = tmp_path / "process.mcap"
    command = record_command(config, out)
    command[1:4] = ["-m", "services.recorder"]
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV
    )
    try:
        assert process.stdout is not None
        assert process.stdout.readline().startswith("recording ")
        publish_all(config, PAYLOADS)
        process.send_signal(signal.SIGHUP)
        _, stderr = process.communicate(timeout=EXIT_TIMEOUT)
    finally:
        process.kill()
        process.wait(10)
    assert process.returncode == 0, stderr
    assert len(whole(out)) == 5


def test_a_demo_whose_terminal_closes_stops_everything_129(tmp_path: Path) -> None:
    """The demo's terminal closes once every process runs: it stops them all
    (none is left), its recording is whole, and it exits 129."""
    out = tmp_path / "results"
    terminal = Terminal([sys.executable, "-m", "armplan", "demo", "--out", str(out)])
    try:
        terminal.wait_for("running:", RUN_TIMEOUT)
        seen = descendants(terminal.process.pid)
        assert len(seen) >= 9
        terminal.close()
        assert terminal.process.wait(STOP_TIMEOUT) == 128 + signal.SIGHUP
        assert [p for p in seen if alive(p)] == []
    finally:
        terminal.kill()
    summarize(out / "session.mcap")  # whole: no recover
