"""``armplan status --json``: its documented shape, against a real router.

A real router process on a free loopback port and a real Zenoh session
holding liveliness tokens, as services hold them; ``armplan status`` runs as
its own process.
"""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Iterator

import pytest
from armplan_cli import armplan

from armplan.launch import SERVICES, free_endpoint
from shared.bus import Bus, load_config
from shared.bus.keys import alive_key

NS = "armplan"


@pytest.fixture
def router() -> Iterator[str]:
    """A router process; yields its endpoint, stops it afterwards."""
    endpoint = free_endpoint()
    process = subprocess.Popen(
        [sys.executable, "-m", "shared.bus.router", "--listen", endpoint],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        Bus.connect(load_config(None, (endpoint,)), wait=30.0).close()
        yield endpoint
    finally:
        process.terminate()
        try:
            process.wait(30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(30)


def test_status_json_gives_keys_as_a_list(router: str) -> None:
    """Every service's keys a list of strings, ``[]`` for a process that
    answers none (the recorder; a token no process of ours holds): they
    were one ", "-joined string, and ``"-"`` for none. The table still
    shows ``-``."""
    with Bus.connect(load_config(None, (router,))) as bus:
        liveliness = bus.session.liveliness()
        tokens = [liveliness.declare_token(alive_key(NS, n)) for n in ("recorder", "x")]
        out = armplan("status", "--connect", router, "--json", "--require", "recorder")
        table = armplan("status", "--connect", router)
        for token in tokens:
            token.undeclare()  # type: ignore[no-untyped-call]
    assert out.returncode == 0, out.stderr
    document = json.loads(out.stdout)
    assert document["router"] == router and document["namespace"] == NS
    services = {s["service"]: s for s in document["services"]}
    assert set(services) == {*(s.name for s in SERVICES), "recorder", "x"}
    assert services["recorder"] == {"service": "recorder", "state": "alive", "keys": []}
    assert services["x"] == {"service": "x", "state": "alive", "keys": []}
    assert services["planner"] == {
        "service": "planner",
        "state": "absent",
        "keys": ["armplan/plan"],
    }
    assert all(
        isinstance(s["keys"], list) and all(isinstance(k, str) for k in s["keys"])
        for s in services.values()
    )
    assert table.returncode == 0, table.stderr
    rows = {line.split()[0]: line.split() for line in table.stdout.splitlines()[1:]}
    assert rows["recorder"] == ["recorder", "alive", "-"]
    assert rows["planner"] == ["planner", "absent", "armplan/plan"]


def test_status_json_without_a_router_is_still_the_document() -> None:
    """No router: ``--json`` printed ``{"error": ...}`` alone, not the
    documented document; now every service is absent and ``error`` is
    added, exit 1 as before."""
    endpoint = free_endpoint()
    out = armplan("status", "--connect", endpoint, "--json")
    assert out.returncode == 1
    document = json.loads(out.stdout)
    assert set(document) == {"router", "namespace", "services", "error"}
    assert (document["router"], document["namespace"]) == (endpoint, NS)
    assert [(s["service"], s["state"]) for s in document["services"]] == [
        (s.name, "absent") for s in SERVICES
    ]
    assert document["error"]["kind"] == "service_unavailable"
    assert document["error"]["evidence"]["service"] == "router"
    assert f"no Zenoh router answers at {endpoint}" in out.stderr


def test_a_required_service_not_alive_names_its_token(router: str) -> None:
    """The ``--require`` error's evidence had ``"key": ""``; it names the
    token looked for, or every token's pattern for several services."""
    one = armplan("status", "--connect", router, "--json", "--require", "ik")
    two = armplan("status", "--connect", router, "--require", "ik", "fit")
    assert (one.returncode, two.returncode) == (1, 1)
    error = json.loads(one.stdout)["error"]
    assert error["evidence"]["key"] == "armplan/alive/ik"
    assert error["message"] == (
        f"service 'ik' is unavailable for armplan/alive/ik: not alive on {router}"
    )
    assert two.stderr == (
        "armplan: error: service 'ik, fit' is unavailable for armplan/alive/*: "
        f"not alive on {router}\n"
    )
