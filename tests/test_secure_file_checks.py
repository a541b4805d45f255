"""The files a secured configuration names are checked at start, not only found.

Keys, the password file and client files left readable by others (0644 after
a copy) started routers and clients without a word, while the docs insist
they be owner-only; a client whose CA file was empty, garbage or the router's
own certificate got the generic "no Zenoh router answers ... or refuses this
client". Now each process warns of a secret others may read (naming the file,
its mode and ``chmod 600``), and a CA file with no authority is refused with
an error naming it. Real bundles from ``armplan certs``, real routers.
"""

from __future__ import annotations

import dataclasses
import grp
import json
import logging
import os
import pathlib
import pwd
import time

import pytest
from native_processes import Native

from armplan.launch import catalog, free_endpoint
from armplan.secure import Bundle, write_bundle
from armplan.secure.certificates import openssl
from shared.bus import Bus, BusConfig, load_config, open_router
from shared.errors import BusConfigError

CA = "transport/link/tls/root_ca_certificate"
#: Longest wait for the router to listen [s].
START_WAIT = 60.0
WANTED = "give the authority's certificate (ca.pem of `armplan certs`)"
#: This process's user, as the warnings name a file's owner.
ME = pwd.getpwuid(os.geteuid()).pw_name


def tls_endpoint() -> str:
    return "tls/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]


def with_ca(bundle: Bundle, path: pathlib.Path) -> BusConfig:
    """The bundle's client configuration trusting the CA file ``path``."""
    config = load_config(bundle.clients["client"])
    given = dict(config.client_settings) | {CA: json.dumps(str(path))}
    return dataclasses.replace(config, client_settings=tuple(given.items()))


def open_warnings(caplog: pytest.LogCaptureFixture) -> list[str]:
    """The warnings about files open to other users, logged so far."""
    return [
        r.getMessage()
        for r in caplog.records
        if r.levelno == logging.WARNING and "is open to other users" in r.getMessage()
    ]


@pytest.mark.parametrize(
    ("content", "problem"),
    [
        ("", f"holds no PEM certificate (-----BEGIN CERTIFICATE-----): {WANTED}"),
        ("garbage\n", "holds no PEM certificate"),
        ("router.key", "holds no PEM certificate"),
        (
            "-----BEGIN CERTIFICATE-----\n@@@\n-----END CERTIFICATE-----\n",
            "cannot be read as a certificate (its PEM is not base64 (",
        ),
        (
            "-----BEGIN CERTIFICATE-----\nAAAA\n-----END CERTIFICATE-----\n",
            "cannot be read as a certificate (its DER is not an X.509 certificate)",
        ),
        (
            "router.pem",
            "holds no certificate authority, only certificates marked CA:FALSE "
            f"that another issued (is it the router's certificate?): {WANTED}",
        ),
    ],
    ids=["empty", "garbage", "key", "not-base64", "not-der", "router-certificate"],
)
def test_a_ca_file_without_an_authority_is_named(
    tmp_path: pathlib.Path, content: str, problem: str
) -> None:
    """With the router running: the client's error is the file, not the router."""
    bundle = write_bundle(tmp_path / "secure", endpoint=tls_endpoint())
    named = bundle.directory / content
    bad = tmp_path / "ca.pem"
    bad.write_text(named.read_text() if named.is_file() else content)
    router = open_router(load_config(bundle.router_config))
    with router, pytest.raises(BusConfigError) as raised:
        Bus.connect(with_ca(bundle, bad), wait=5).close()
    assert raised.value.setting == CA
    assert raised.value.message.startswith(
        f"Zenoh configuration {bundle.clients['client']} ({CA}): {bad} {problem}"
    )


def test_a_ca_file_holding_the_authority_among_others_is_taken(
    tmp_path: pathlib.Path,
) -> None:
    """router.pem, then ca.pem, in one file: the client connects."""
    bundle = write_bundle(tmp_path / "secure", endpoint=tls_endpoint())
    both = tmp_path / "both.pem"
    both.write_text(
        (bundle.directory / "router.pem").read_text()
        + (bundle.directory / "ca.pem").read_text()
    )
    router = open_router(load_config(bundle.router_config))
    with router, Bus.connect(with_ca(bundle, both), wait=30) as bus:
        assert bus.session.info.routers_zid()


def test_a_self_signed_router_certificate_marked_ca_false_is_trusted(
    tmp_path: pathlib.Path,
) -> None:
    """The usual way to trust a self-signed router: its own certificate as the
    CA file of router and client. rustls takes a self-signed server
    certificate only when marked CA:FALSE; the check refused it as "holds no
    certificate authority". Made by the real openssl; a real router and
    client connect."""
    bundle = write_bundle(tmp_path / "secure", endpoint=tls_endpoint())
    folder = bundle.directory
    openssl(
        [
            *("req", "-x509", "-newkey", "ec", "-pkeyopt"),
            *("ec_paramgen_curve:P-256", "-nodes", "-days", "30"),
            *("-keyout", str(folder / "router.key"), "-out", str(folder / "ca.pem")),
            *("-subj", "/CN=armplan router", "-addext"),
            *("basicConstraints=critical,CA:FALSE", "-addext"),
            *("subjectAltName=IP:127.0.0.1", "-addext"),
            "extendedKeyUsage=serverAuth",
        ]
    )
    (folder / "router.pem").write_bytes((folder / "ca.pem").read_bytes())
    router = open_router(load_config(bundle.router_config))
    with router, Bus.connect(load_config(bundle.clients["client"]), wait=30) as bus:
        assert bus.session.info.routers_zid()


def test_a_router_warns_of_its_key_and_passwords_open_to_others(
    tmp_path: pathlib.Path,
) -> None:
    """router.key 0644, passwords.txt 0640: two warnings, and it listens;
    router.json5 0644 holds no password (no --connect): no warning."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    (tmp_path / "router.key").chmod(0o644)
    (tmp_path / "passwords.txt").chmod(0o640)
    bundle.router_config.chmod(0o644)
    router = Native(
        "router",
        ["python", "-m", catalog.ROUTER_MODULE, "--config", str(bundle.router_config)],
        tmp_path / "router.log",
    )
    try:
        deadline = time.monotonic() + START_WAIT
        while "router listening" not in router.output():
            assert router.running() and time.monotonic() < deadline, router.output()
            time.sleep(0.1)
    finally:
        router.stop()
    output = router.output()
    for name, held, mode in [
        ("router.key", "a private key", "0644"),
        ("passwords.txt", "every user's password", "0640"),
    ]:
        path = tmp_path / name
        assert (
            f"WARNING {path} holds {held} and is open to other users (mode {mode}, "
            f"owner {ME}): make it readable by its owner only: chmod 600 {path}\n"
        ) in output
    assert output.count("is open to other users") == 2


def test_a_client_warns_of_its_file_open_to_others(
    tmp_path: pathlib.Path, caplog: pytest.LogCaptureFixture
) -> None:
    """client.json5 holds a password: at 0644 a warning, at 0600 (as written) none."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    client = bundle.clients["client"]
    caplog.set_level(logging.WARNING, logger="armplan.bus")
    with open_router(load_config(bundle.router_config)):
        with Bus.connect(load_config(client), wait=30):
            assert open_warnings(caplog) == []
        client.chmod(0o644)
        with Bus.connect(load_config(client), wait=30):
            pass
    assert open_warnings(caplog) == [
        f"{client} holds a password and is open to other users (mode 0644, "
        f"owner {ME}): make it readable by its owner only: chmod 600 {client}"
    ]


#: Another user and group to own a shared key: daemon's, as on most systems.
OTHER = pwd.getpwnam("daemon")
OTHER_GROUP = grp.getgrgid(OTHER.pw_gid).gr_name


@pytest.mark.skipif(
    os.geteuid() != 0, reason="giving a file to another user needs root"
)
@pytest.mark.parametrize(
    ("mode", "warned"),
    [(0o640, False), (0o600, False), (0o644, True), (0o660, True), (0o604, True)],
    ids=["0640", "0600", "0644", "0660", "0604"],
)
def test_a_key_another_user_shares_with_its_group_may_be_group_readable(
    tmp_path: pathlib.Path, caplog: pytest.LogCaptureFixture, mode: int, warned: bool
) -> None:
    """router.key owned by another user (as root:ssl-cert 0640, read by a
    service in the group): 0640 passes quietly, since `chmod 600` would lock
    the service out; group write or any access by others is warned of,
    naming owner and group and chmod 640. A real router listens each time."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    key = tmp_path / "router.key"
    os.chown(key, OTHER.pw_uid, OTHER.pw_gid)
    key.chmod(mode)
    caplog.set_level(logging.WARNING, logger="armplan.bus")
    with open_router(load_config(bundle.router_config)):
        pass
    assert open_warnings(caplog) == (
        [
            f"{key} holds a private key and is open to other users (mode "
            f"{mode:04o}, owner daemon, group {OTHER_GROUP}): make it readable by "
            f"its owner and group only (this process's user in group "
            f"{OTHER_GROUP}): chmod 640 {key}, as daemon"
        ]
        if warned
        else []
    )
