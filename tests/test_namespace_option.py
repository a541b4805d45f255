"""``--namespace NS`` on every command that joins or starts an armplan system.

Two systems on one router, each in its own namespace: ``armplan status``,
the client commands' ``--remote`` options, ``armplan up`` and the processes
it starts (services, bridge) took no ``--namespace`` and were bound to the
config's. Real routers, real service processes, real ``armplan`` commands,
each on a free loopback port.
"""

from __future__ import annotations

import json
import os
import pathlib
import signal
import subprocess
import sys
from collections.abc import Iterator

import pytest

from armplan.launch import Launcher, free_endpoint
from shared.bus import BusConfig, load_config
from shared.bus.options import with_namespace
from tests.test_launcher import EXIT_TIMEOUT, armplan, armplan_up

REPO = pathlib.Path(__file__).resolve().parents[1]
#: The namespace the second system runs in; the config's is ``armplan``.
LAB = "lab2"
IK = ["ik", "--target", "0.12", "-0.13", "0.05", "--json"]
#: A robot address nothing listens on (in this suite's port range): the
#: bridge starts without its robot and reaches it only on a request.
NO_ROBOT = free_endpoint().replace("tcp/", "tcp://")  # nothing listens


@pytest.fixture(scope="module")
def lab() -> Iterator[BusConfig]:
    """A router and an IK service started in namespace ``LAB``."""
    config = with_namespace(load_config(endpoints=(free_endpoint(),)), LAB)
    with Launcher(config, ["ik"], log=subprocess.DEVNULL):
        yield config


def status(*args: str) -> dict[str, str]:
    """``armplan status --json ARGS``: each service's state, by name."""
    out = armplan("status", "--json", *args)
    document = json.loads(out.stdout)
    return {s["service"]: s["state"] for s in document["services"]}


def test_status_lists_the_services_of_the_namespace_asked(lab: BusConfig) -> None:
    """`status --namespace NS` sees the ik service alive in NS; plain
    `status` asks the config's namespace, where it is absent (status took
    no --namespace: only the config's namespace could be asked about)."""
    asked = armplan("status", "--connect", lab.endpoint, "--namespace", LAB, "--json")
    assert asked.returncode == 0, asked.stderr
    document = json.loads(asked.stdout)
    assert document["namespace"] == LAB
    ik = next(s for s in document["services"] if s["service"] == "ik")
    assert ik == {
        "service": "ik",
        "state": "alive",
        "keys": [f"{LAB}/ik/solve", f"{LAB}/ik/path"],
    }
    assert status("--connect", lab.endpoint)["ik"] == "absent"
    required = armplan("status", "--connect", lab.endpoint, "--require", "ik")
    assert required.returncode == 1
    assert "not alive on" in required.stderr


def test_a_client_asks_the_services_of_its_namespace(lab: BusConfig) -> None:
    """`ik --connect E --namespace NS` is answered by NS's service, as
    in-process; without it, the config's namespace has no ik service."""
    remote = armplan(*IK, "--connect", lab.endpoint, "--namespace", LAB)
    assert remote.returncode == 0, remote.stderr
    assert remote.stdout == armplan(*IK).stdout
    default = armplan(*IK, "--connect", lab.endpoint)
    assert default.returncode == 1 and "Traceback" not in default.stderr
    assert "service 'ik' is unavailable for armplan/ik/solve" in default.stderr


def test_namespace_alone_implies_remote(tmp_path: pathlib.Path) -> None:
    """`ik --namespace NS` asks the services (as --connect and --zenoh-config
    do): with no router at the config's endpoint, the no-router error, not a
    posture solved in-process."""
    missing = free_endpoint()
    text = (REPO / "config" / "zenoh.json5").read_text()
    config = tmp_path / "elsewhere.json5"
    config.write_text(text.replace('"tcp/127.0.0.1:7447"', f'"{missing}"'))
    out = subprocess.run(
        [sys.executable, "-m", "armplan", *IK, "--namespace", LAB],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        env={**os.environ, "ARMPLAN_ZENOH_CONFIG": str(config)},
    )
    assert out.returncode == 1 and "Traceback" not in out.stderr
    assert f"no Zenoh router answers at {missing}" in out.stderr


def test_up_starts_every_child_in_the_namespace_given(tmp_path: pathlib.Path) -> None:
    """`up --namespace NS`: the service and the bridge serve under NS (the
    printed lines say so), the config's namespace has none of them."""
    endpoint = free_endpoint()
    args = ["--listen", endpoint, "--namespace", LAB, "--only", "ik"]
    with armplan_up(
        *args, "--with-bridge", "--robot", NO_ROBOT, log=tmp_path / "up.log"
    ) as up:
        lines = up.wait_ready()
        text = "\n".join(lines)
        assert f"listening on {endpoint} (namespace {LAB}, " in text
        assert f"{LAB}/ik/solve, {LAB}/ik/path" in text
        assert f"{LAB}/bridge/execute -> robot {NO_ROBOT}" in text
        assert lines[-1].startswith("armplan up: ready, alive: bridge, ik;")
        states = status("--connect", endpoint, "--namespace", LAB)
        assert (states["ik"], states["bridge"]) == ("alive", "alive")
        default = status("--connect", endpoint)
        assert default["ik"] == "absent" and "bridge" not in default
        up.process.send_signal(signal.SIGINT)
        assert up.process.wait(EXIT_TIMEOUT) == 0


#: A wildcard, a '/' at either end: no namespace.
MALFORMED = ["lab/*", "/lab", "lab/"]


@pytest.mark.parametrize(
    "command",
    [
        ["status"],
        ["up", "--only", "ik"],
        IK,
        ["plan", "--target", "0.12", "-0.13", "0.05"],
        ["decide", "--target", "0.12", "-0.13", "0.05"],
        ["fit", "--show"],
    ],
    ids=lambda c: c[0],
)
@pytest.mark.parametrize("namespace", MALFORMED)
def test_a_malformed_namespace_is_the_config_error(
    command: list[str], namespace: str
) -> None:
    """Exit 1 naming the namespace and the option, no traceback, nothing
    started (status and the clients refused the option: exit 2)."""
    router = "--listen" if command[0] == "up" else "--connect"
    out = armplan(*command, router, free_endpoint(), "--namespace", namespace)
    assert out.returncode == 1, out.stderr
    assert "Traceback" not in out.stderr
    assert f"+ --namespace (namespace): namespace {namespace!r} must be" in (out.stderr)
    assert "listening" not in out.stdout + out.stderr


@pytest.mark.parametrize("module", ["services.ik", "services.planner", "bridge.serve"])
def test_a_process_given_a_malformed_namespace_exits_1_naming_it(module: str) -> None:
    """A service or the bridge given `--namespace lab/*`: exit 1 with the
    error logged (they took no --namespace: argparse's exit 2)."""
    out = subprocess.run(
        [
            *(sys.executable, "-m", module),
            *("--connect", free_endpoint(), "--namespace", "lab/*", "--wait", "1"),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert out.returncode == 1, out.stderr
    assert "Traceback" not in out.stderr
    assert "+ --namespace (namespace): namespace 'lab/*' must be" in out.stderr
