"""`armplan up` and `armplan demo` refuse the secured set before starting anything.

`up --config secure/client.json5 --listen tcp/...` looked only at the
endpoint --listen had put in, and `demo` did not look at all: both started a
plain router whose services failed after a minute as if no router answered.
`up --listen tls/...` with the plain repository file called that file "a
secured (TLS) configuration". Each command runs as its own process (with a
timeout: on the old code they ran on).
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

from armplan.launch import free_endpoint
from armplan.secure import Bundle, write_bundle

ROOT = pathlib.Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Bundle:
    port = free_endpoint().rsplit(":", 1)[1]
    return write_bundle(
        tmp_path_factory.mktemp("secure"), endpoint=f"tls/127.0.0.1:{port}"
    )


def armplan(*args: str, cwd: pathlib.Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("ARMPLAN_ZENOH_CONFIG", None)
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=90,
        check=False,
        cwd=cwd,
        env=env,
    )


def assert_nothing_started(done: subprocess.CompletedProcess[str]) -> None:
    assert done.returncode == 1, done.stdout + done.stderr
    for started in ("listening", "ready", "router   pid", "starting"):
        assert started not in done.stdout + done.stderr


@pytest.mark.parametrize("command", ["up", "demo"])
@pytest.mark.parametrize("user", ["client", "ik"])
def test_a_client_file_with_a_plain_listen_is_refused(
    bundle: Bundle, tmp_path: pathlib.Path, command: str, user: str
) -> None:
    """The file's own endpoint and login count, not --listen's tcp/."""
    path = bundle.clients[user]
    done = armplan(
        command, "--config", str(path), "--listen", free_endpoint(), cwd=tmp_path
    )
    assert_nothing_started(done)
    assert done.stderr.startswith(
        f"armplan: error: {path} is a secured configuration (listen/endpoints, "
        "transport/auth/usrpwd/user, transport/auth/usrpwd/password, "
        f"transport/link/tls/root_ca_certificate): armplan {command} runs the "
        "unsecured set"
    )
    assert not (tmp_path / "armplan-demo").exists()


def test_demo_refuses_the_secured_router_file(
    bundle: Bundle, tmp_path: pathlib.Path
) -> None:
    done = armplan("demo", "--config", str(bundle.router_config), cwd=tmp_path)
    assert_nothing_started(done)
    assert "transport/auth/usrpwd/dictionary_file" in done.stderr
    assert "access_control/enabled" in done.stderr


def test_a_login_alone_makes_a_file_secured(
    bundle: Bundle, tmp_path: pathlib.Path
) -> None:
    """A client file moved to a tcp/ endpoint still logs in: refused."""
    text = bundle.clients["client"].read_text()
    endpoint = free_endpoint()
    tls = text.split('"endpoints": [\n')[1].split("\n")[0].strip()
    plain = tmp_path / "plain-endpoint.json5"
    plain.write_text(text.replace(tls, f'"{endpoint}"'))
    done = armplan("up", "--config", str(plain), cwd=tmp_path)
    assert_nothing_started(done)
    assert f"{plain} is a secured configuration (transport/auth/usrpwd/user" in (
        done.stderr
    )


@pytest.mark.parametrize("command", ["up", "demo"])
def test_a_tls_listen_with_the_plain_file_names_the_option(
    tmp_path: pathlib.Path, command: str
) -> None:
    """Not 'config/zenoh.json5 is a secured (TLS) configuration': --listen."""
    endpoint = "tls/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]
    done = armplan(command, "--listen", endpoint, cwd=tmp_path)
    assert_nothing_started(done)
    assert done.stderr.startswith(
        f"armplan: error: --listen {endpoint}: armplan {command} runs the "
        "unsecured router, which listens on tcp/"
    )
    assert "zenoh.json5" not in done.stderr


@pytest.mark.parametrize("command", ["up", "demo"])
@pytest.mark.parametrize("protocol", ["udp", "ws"])
def test_a_listen_other_than_tcp_is_refused(
    tmp_path: pathlib.Path, command: str, protocol: str
) -> None:
    """udp/ was taken, and the demo then lost a call and failed at random."""
    endpoint = f"{protocol}/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]
    done = armplan(command, "--listen", endpoint, cwd=tmp_path)
    assert_nothing_started(done)
    assert done.stderr.startswith(
        f"armplan: error: --listen {endpoint}: armplan {command} runs its router "
        f"on tcp/ only (e.g. tcp/127.0.0.1:7447): the services' calls need its "
        f"reliable, ordered stream, which {protocol}/ is not"
    )
    assert not (tmp_path / "armplan-demo").exists()


def test_up_refuses_a_file_listening_on_udp(tmp_path: pathlib.Path) -> None:
    """The file's own endpoint counts when no --listen replaces it."""
    endpoint = "udp/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]
    text = (ROOT / "config" / "zenoh.json5").read_text()
    udp = tmp_path / "udp.json5"
    udp.write_text(text.replace("tcp/127.0.0.1:7447", endpoint))
    assert endpoint in udp.read_text()
    done = armplan("up", "--config", str(udp), cwd=tmp_path)
    assert_nothing_started(done)
    assert f"error: {udp} endpoint {endpoint}: armplan up runs its router on tcp/" in (
        done.stderr
    )
