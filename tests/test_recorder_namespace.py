"""Keys and namespace of a recorder: the mistakes that recorded 0 messages.

``--keys armplan/plan/trajectory`` (the full key, copied from ``armplan
inspect``) is refused naming the relative form; a recorder whose namespace
has no armplan process alive warns, naming the namespaces that have one.
Real router, real processes and liveliness tokens.
"""

from __future__ import annotations

import logging
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest
from record_cli import record_command

from armplan.launch import free_endpoint
from services.recorder.options import RecorderOptions
from services.recorder.service import Recorder
from shared.bus import Bus, BusConfig, open_router
from shared.errors import InvalidInputError

NS = "recns"


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NS)
    with open_router(config):
        yield config


def test_a_key_with_the_namespace_is_refused_naming_the_relative_one(
    config: BusConfig, tmp_path: Path
) -> None:
    """`armplan record --keys recns/misc/*`: exit 1, one line, no file."""
    out = tmp_path / "s.mcap"
    command = record_command(config, out, "--duration", "2")
    command[command.index("misc/*")] = f"{NS}/misc/*"
    process = subprocess.run(
        command,
        capture_output=True,
        text=True,
        env={**os.environ, "ARMPLAN_ZENOH_CONFIG": ""},
        timeout=60,
        check=False,
    )
    assert process.returncode == 1, process.stderr
    assert process.stderr == (
        f"armplan: error: --keys {NS}/misc/* starts with the namespace {NS!r}: "
        f"keys are relative to it, give misc/* (this would record "
        f"{NS}/{NS}/misc/*)\n"
    )
    assert not out.exists()


def test_a_key_like_the_namespace_but_longer_is_kept(
    config: BusConfig, tmp_path: Path
) -> None:
    """`recnsx/a` is a key under the namespace, not the namespace itself."""
    options = RecorderOptions(output=tmp_path / "s.mcap", keys=(f"{NS}x/a",))
    with Bus.connect(config) as bus:
        assert Recorder(bus, options).keys == [f"{NS}/{NS}x/a"]
        with pytest.raises(InvalidInputError, match="give plan/trajectory"):
            Recorder(bus, RecorderOptions(keys=(f"{NS}/plan/trajectory",)))


def _start_recorder(
    config: BusConfig, namespace: str, out: Path, caplog: pytest.LogCaptureFixture
) -> list[str]:
    """Start and stop a recorder under ``namespace``; the warnings it logged."""
    caplog.clear()
    theirs = BusConfig(endpoints=config.endpoints, namespace=namespace)
    options = RecorderOptions(output=out, keys=("**",), foxglove=False)
    with (
        caplog.at_level(logging.WARNING, logger="armplan.recorder"),
        Bus.connect(theirs) as bus,
        Recorder(bus, options),
    ):
        pass
    return [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]


def test_a_namespace_with_nobody_alive_is_named_with_those_alive(
    config: BusConfig, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A planner alive under recns: a recorder under nao1 warns and names
    recns; one under recns does not warn; another recorder does not count."""
    with Bus.connect(config) as services:
        token = services.session.liveliness().declare_token(f"{NS}/alive/planner")
        other = services.session.liveliness().declare_token("nao1/alive/recorder")
        try:
            wrong = _start_recorder(config, "nao1", tmp_path / "a.mcap", caplog)
            right = _start_recorder(config, NS, tmp_path / "b.mcap", caplog)
        finally:
            token.undeclare()  # type: ignore[no-untyped-call]
            other.undeclare()  # type: ignore[no-untyped-call]
    assert wrong == [
        "recorder: no armplan process is alive in namespace 'nao1', so nothing "
        f"is published under nao1/ yet; processes are alive under {NS!r}: check "
        "--namespace"
    ]
    assert right == []


def test_a_recorder_started_first_warns_without_refusing(
    config: BusConfig, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """Nobody alive anywhere: a warning, and the recording is made."""
    out = tmp_path / "first.mcap"
    said = _start_recorder(config, "early", out, caplog)
    assert said == [
        "recorder: no armplan process is alive in namespace 'early', so nothing "
        "is published under early/ yet; it records what they publish once "
        "they start"
    ]
    assert out.exists()
