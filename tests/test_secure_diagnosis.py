"""A refused connection can be told apart: the router's log, the missing file.

The Python router never started Zenoh's log, so a wrong password left no
trace (even with RUST_LOG=debug); a client whose CA file had gone (the bundle
folder moved) got the same "no router answers ... or refuses" as for a wrong
password; a router whose password file or key had gone said "is another
router using it?". Now the secured router logs each refused login, never a
password (Zenoh's general debug log would print its configuration), and
clients and routers name a missing file before opening anything.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
import shutil
import time

import pytest
from native_processes import Native

from armplan.launch import catalog, free_endpoint
from armplan.secure import Bundle, write_bundle
from armplan.secure.passwords import read_passwords
from shared.bus import Bus, BusConfig, load_config, open_router
from shared.errors import BusConfigError, ServiceUnavailableError

#: How long the router's log is watched for a line [s].
LOG_WAIT = 30.0


def tls_endpoint() -> str:
    return "tls/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]


def start_router(bundle: Bundle, folder: pathlib.Path) -> Native:
    """The secured router, with RUST_LOG=debug in its environment."""
    argv = ["python", "-m", catalog.ROUTER_MODULE]
    return Native(
        "router",
        [*argv, "--config", str(bundle.router_config)],
        folder / "router.log",
        env={"RUST_LOG": "debug"},
    )


def wait_for_line(router: Native, text: str) -> str:
    """The router's output once it holds ``text`` (fails after LOG_WAIT)."""
    deadline = time.monotonic() + LOG_WAIT
    while text not in router.output():
        assert router.running() and time.monotonic() < deadline, router.output()
        time.sleep(0.1)
    return router.output()


def user_config(bundle: Bundle, user: str, **settings: str) -> BusConfig:
    """The user's client configuration, with some client settings replaced."""
    config = load_config(bundle.clients[user])
    given = dict(config.client_settings)
    given.update({k: json.dumps(v) for k, v in settings.items()})
    return dataclasses.replace(config, client_settings=tuple(given.items()))


def refused(config: BusConfig) -> None:
    with pytest.raises(ServiceUnavailableError):
        Bus.connect(config, wait=5).close()


def test_the_router_logs_refused_logins_and_no_password(
    tmp_path: pathlib.Path,
) -> None:
    """A wrong password and an unknown user are logged; no password ever is.

    Router B connects to router A with its password in B's router.json5: B's
    log, with RUST_LOG=debug in its environment, holds no password either.
    """
    bundle_a = write_bundle(tmp_path / "a", endpoint=tls_endpoint())
    folder_b = tmp_path / "b"
    folder_b.mkdir()
    for name in ("ca.pem", "ca.key", "passwords.txt"):
        shutil.copy2(bundle_a.directory / name, folder_b / name)
    endpoint_a = load_config(bundle_a.router_config).endpoint
    bundle_b = write_bundle(folder_b, endpoint=tls_endpoint(), connect=[endpoint_a])
    router_a = start_router(bundle_a, bundle_a.directory)
    router_b = start_router(bundle_b, folder_b)
    try:
        wait_for_line(router_a, "router listening")
        wait_for_line(router_b, "router listening")
        with Bus.connect(load_config(bundle_a.clients["client"]), wait=30):
            pass
        password = "transport/auth/usrpwd/password"
        refused(user_config(bundle_a, "client", **{password: "wrong"}))
        wait_for_line(router_a, "Invalid password")
        user = "transport/auth/usrpwd/user"
        refused(user_config(bundle_a, "client", **{user: "intruder"}))
        wait_for_line(router_a, "Invalid user")
        with Bus.connect(load_config(bundle_b.clients["client"]), wait=30) as bus:
            assert bus.session.info.routers_zid()  # B reached: B logged in at A
    finally:
        router_a.stop()
        router_b.stop()
    logs = router_a.output() + router_b.output()
    assert "New transport link accepted" in router_a.output()
    for secret in read_passwords(bundle_a.directory / "passwords.txt").values():
        assert secret not in logs
    assert "dictionary_file" not in logs  # the configuration is not printed


def test_a_client_names_a_ca_file_that_is_gone(tmp_path: pathlib.Path) -> None:
    """The bundle's folder moved: its client file's CA path names nothing."""
    bundle = write_bundle(tmp_path / "secure", endpoint=tls_endpoint())
    moved = tmp_path / "moved"
    bundle.directory.rename(moved)
    with pytest.raises(BusConfigError) as raised:
        Bus.connect(load_config(moved / "client.json5"))
    assert raised.value.message == (
        f"Zenoh configuration {moved / 'client.json5'} "
        "(transport/link/tls/root_ca_certificate): "
        f"{bundle.directory / 'ca.pem'} does not exist: was the folder moved? "
        "Rerun `armplan certs --out DIR` where the files are now (or give "
        "--paths), or correct the path"
    )


@pytest.mark.parametrize(
    ("name", "setting"),
    [
        ("passwords.txt", "transport/auth/usrpwd/dictionary_file"),
        ("router.key", "transport/link/tls/listen_private_key"),
    ],
)
def test_a_router_names_a_missing_file(
    tmp_path: pathlib.Path, name: str, setting: str
) -> None:
    """Not 'is another router using it?': the file and its setting."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    (tmp_path / name).unlink()
    with pytest.raises(BusConfigError) as raised:
        open_router(load_config(bundle.router_config)).close()
    assert raised.value.setting == setting
    assert f"{tmp_path / name} does not exist" in raised.value.message
    assert "another router" not in raised.value.message


def test_a_key_of_another_certificate_is_named(tmp_path: pathlib.Path) -> None:
    bundle = write_bundle(tmp_path / "a", endpoint=tls_endpoint())
    write_bundle(tmp_path / "b")
    shutil.copy2(tmp_path / "b" / "router.key", tmp_path / "a" / "router.key")
    with pytest.raises(BusConfigError) as raised:
        open_router(load_config(bundle.router_config)).close()
    assert raised.value.message.endswith(
        "the router's key does not belong to its certificate: rerun "
        "`armplan certs --out DIR`, which writes both"
    )


def test_a_secured_client_is_not_told_to_run_armplan_up(
    tmp_path: pathlib.Path,
) -> None:
    """`armplan up` refuses TLS files: the error names the secured router."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    with pytest.raises(ServiceUnavailableError) as raised:
        Bus.connect(load_config(bundle.clients["client"]))
    message = raised.value.message
    assert "or one answers but refuses this client" in message
    assert "must name the endpoint's host: `armplan certs --host`" in message
    assert message.endswith(
        "start the secured router with `python -m shared.bus.router --config "
        "DIR/router.json5`, or give its address with --connect"
    )
    assert "armplan up" not in message


def test_an_unsecured_client_is_told_of_a_secured_router(
    tmp_path: pathlib.Path,
) -> None:
    """Plain TCP to a TLS router's port: the error names the secured router
    and the client file, not only `armplan up` (which finds the port taken)."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    router_config = load_config(bundle.router_config)
    port = router_config.endpoint.rsplit(":", 1)[1]
    with open_router(router_config):
        plain = load_config(endpoints=(f"tcp/127.0.0.1:{port}",))
        with pytest.raises(ServiceUnavailableError) as raised:
            Bus.connect(plain).close()
    message = raised.value.message
    assert f"no Zenoh router answers at tcp/127.0.0.1:{port}" in message
    assert message.endswith(
        "start one with `armplan up`, or give the router's address with "
        "--connect. If a secured router (TLS) is there, it refuses this unsecured "
        "client: give the client file `armplan certs` wrote (--config "
        "DIR/client.json5)"
    )
