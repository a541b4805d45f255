""" "Not alive" errors name the token watched, and where else it is alive.

``armplan replay --namespace lab2 --wait-for bridge`` with the bridge alive
under another namespace said only "not alive after 5 s". A real router, a
real Zenoh session holding a liveliness token under another namespace (as a
service there holds it) and ``armplan`` run as its own process.
"""

from __future__ import annotations

import json
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from armplan_cli import armplan

from armplan.launch import free_endpoint
from shared.bus import Bus, BusConfig, open_router
from shared.bus.elsewhere import elsewhere_hint
from shared.bus.keys import alive_anywhere, alive_key, namespace_from_alive_key
from shared.bus.routes import IK_SOLVE
from shared.errors import ServiceUnavailableError, error_from_wire
from shared.messages import IKRequest
from shared.recording.writer import MessageWriter

#: The namespace the services run under; the clients watch another one.
OTHER = "lab1"
MINE = "lab2"
REQUEST = IKRequest(target=(0.12, -0.13, 0.05))
HINT = f"; 'bridge' is alive in namespace '{OTHER}' (--namespace {OTHER})"


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace=MINE)
    with open_router(config):
        yield config


def hold_token(bus: Bus, namespace: str, service: str) -> zenoh.LivelinessToken:
    """Declare ``service``'s token under ``namespace``; wait until it is seen."""
    token = bus.session.liveliness().declare_token(alive_key(namespace, service))
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        if any(
            r.ok is not None
            for r in bus.session.liveliness().get(
                alive_key(namespace, service), timeout=1.0
            )
        ):
            break
        time.sleep(0.05)
    return token


@pytest.fixture
def bridge_elsewhere(config: BusConfig) -> Iterator[None]:
    """``bridge`` and ``ik`` alive under ``OTHER`` while the test runs."""
    with Bus.connect(config) as bus:
        tokens = [hold_token(bus, OTHER, name) for name in ("bridge", "ik")]
        yield
        for token in tokens:
            token.undeclare()  # type: ignore[no-untyped-call]


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small recording of one message to replay."""
    path = tmp_path_factory.mktemp("elsewhere") / "one.mcap"
    with MessageWriter(path, chunked=False) as writer:
        writer.write(f"{MINE}/misc/request", REQUEST, time.time_ns())
    return path


def replay_waiting(config: BusConfig, path: Path) -> subprocess.CompletedProcess[str]:
    return armplan(
        *("replay", str(path), "--wait-for", "bridge", "--wait", "0.5"),
        *("--connect", config.endpoint, "--namespace", MINE),
    )


def test_the_pattern_of_a_service_in_every_namespace() -> None:
    assert alive_anywhere("bridge") == "**/alive/bridge"
    assert namespace_from_alive_key("robots/nao1/alive/bridge", "bridge") == (
        "robots/nao1"
    )
    assert namespace_from_alive_key("alive/bridge", "bridge") == ""


def test_replay_names_the_namespace_where_the_bridge_is_alive(
    config: BusConfig, recording: Path, bridge_elsewhere: None
) -> None:
    out = replay_waiting(config, recording)
    assert out.returncode == 1
    assert out.stderr == (
        "armplan: error: service 'bridge' is unavailable: no liveliness token on "
        f"{MINE}/alive/bridge after 0.5 s{HINT}\n"
    )


def test_replay_with_the_bridge_nowhere_names_the_key_only(
    config: BusConfig, recording: Path
) -> None:
    out = replay_waiting(config, recording)
    assert out.returncode == 1
    assert out.stderr == (
        "armplan: error: service 'bridge' is unavailable: no liveliness token on "
        f"{MINE}/alive/bridge after 0.5 s\n"
    )


def test_a_call_names_the_namespace_where_its_service_is_alive(
    config: BusConfig, bridge_elsewhere: None
) -> None:
    with Bus.connect(config) as bus, pytest.raises(ServiceUnavailableError) as info:
        bus.call(IK_SOLVE, REQUEST, timeout=2.0)
    error = info.value
    assert error.elsewhere == {"ik": [OTHER]}
    assert error.reason.startswith(f"no liveliness token at {MINE}/alive/ik ")
    assert error.reason.endswith(
        f"; 'ik' is alive in namespace '{OTHER}' (--namespace {OTHER})"
    )
    again = error_from_wire(json.loads(json.dumps(error.to_wire())))
    assert isinstance(again, ServiceUnavailableError)
    assert (again.message, again.evidence) == (error.message, error.evidence)


def test_a_call_with_its_service_nowhere_has_no_hint(config: BusConfig) -> None:
    with Bus.connect(config) as bus, pytest.raises(ServiceUnavailableError) as info:
        bus.call(IK_SOLVE, REQUEST, timeout=2.0)
    assert info.value.elsewhere == {}
    assert "is alive in namespace" not in info.value.message


def test_status_require_names_the_namespace_where_it_is_alive(
    config: BusConfig,
) -> None:
    """``armplan status`` watches ``armplan``; the bridge is alive in ``lab1``."""
    with Bus.connect(config) as bus:
        token = hold_token(bus, OTHER, "bridge")
        try:
            table = armplan(
                "status", "--connect", config.endpoint, "--require", "bridge"
            )
            document = armplan(
                *("status", "--connect", config.endpoint, "--json"),
                *("--require", "bridge", "ik"),
            )
        finally:
            token.undeclare()  # type: ignore[no-untyped-call]
    assert (table.returncode, document.returncode) == (1, 1)
    assert table.stderr == (
        "armplan: error: service 'bridge' is unavailable for armplan/alive/bridge: "
        f"not alive on {config.endpoint}{HINT}\n"
    )
    error = json.loads(document.stdout)["error"]
    assert error["evidence"]["elsewhere"] == {"bridge": [OTHER]}
    assert error["message"].endswith(HINT)


def test_a_hint_names_at_most_three_namespaces_then_how_many_more() -> None:
    """Names from the network: a router holding a service in thousands of
    namespaces made a message thousands of names long."""
    many = {"bridge": [f"lab{k:04d}" for k in range(2000)]}
    hint = elsewhere_hint(many)
    assert hint == (
        "; 'bridge' is alive in namespaces 'lab0000', 'lab0001', 'lab0002' "
        "and 1997 more (--namespace lab0000)"
    )
    assert elsewhere_hint({"ik": ["lab1"]}) == (
        "; 'ik' is alive in namespace 'lab1' (--namespace lab1)"
    )


def test_stop_without_a_bridge_names_the_commands_that_start_one(
    config: BusConfig,
) -> None:
    """``armplan stop`` right after a plain ``armplan up`` (which starts no
    bridge) asked "is it started, e.g. by `armplan up`?"."""
    done = armplan("stop", "--connect", config.endpoint, "--namespace", MINE)
    assert done.returncode == 1
    assert done.stderr == (
        f"armplan: error: service 'bridge' is unavailable for {MINE}/bridge/stop: "
        f"no liveliness token at {MINE}/alive/bridge (is it started, e.g. by "
        "`armplan up --with-sim`, `armplan up --robot URL` or `python -m "
        "bridge.serve`?); the query was sent all the same: nothing answered\n"
    )
