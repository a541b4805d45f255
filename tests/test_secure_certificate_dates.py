"""Certificates near or past their end: the router and `armplan certs` say so.

An expired router certificate let the router log "listening" while every
client failed with the generic "no router answers ... or refuses this client";
nothing said "expired". Now the router refuses to start naming the file and
the date, warns within 30 days of the end, and `armplan certs` warns about a
kept authority that has expired or soon will. Certificates past their end are
made with the real openssl (``-days -1``).
"""

from __future__ import annotations

import pathlib
import subprocess
import time
from datetime import UTC, datetime, timedelta

import pytest
from native_processes import Native

from armplan.cli.main import main
from armplan.launch import catalog, free_endpoint
from armplan.secure import write_bundle
from armplan.secure.certificates import openssl
from shared.bus import load_config
from shared.bus.certificate_dates import check_listen_certificate, read_validity
from shared.errors import BusConfigError


def openssl_end(path: pathlib.Path) -> datetime:
    """The certificate's notAfter as openssl prints it."""
    done = subprocess.run(
        ["openssl", "x509", "-in", str(path), "-noout", "-enddate"],
        capture_output=True,
        text=True,
        check=True,
    )
    text = done.stdout.strip().removeprefix("notAfter=")
    return datetime.strptime(text, "%b %d %H:%M:%S %Y GMT").replace(tzinfo=UTC)


def tls_endpoint() -> str:
    return "tls/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]


def expire_router_certificate(folder: pathlib.Path) -> None:
    """Reissue router.pem from its own key and the folder's CA, ended yesterday."""
    request = folder / "router.csr"
    key = str(folder / "router.key")
    openssl(["req", "-new", "-key", key, "-out", str(request), "-subj", "/CN=r"])
    openssl(
        [
            *("x509", "-req", "-in", str(request), "-CA", str(folder / "ca.pem")),
            *("-CAkey", str(folder / "ca.key"), "-CAcreateserial"),
            *("-out", str(folder / "router.pem"), "-days", "-1"),
        ]
    )


@pytest.mark.parametrize("days", [1, 825, 36_500])
def test_the_dates_read_are_openssls(tmp_path: pathlib.Path, days: int) -> None:
    """The end date agrees with openssl's, in UTCTime and GeneralizedTime."""
    write_bundle(tmp_path, days=days)
    for name in ("ca.pem", "router.pem"):
        validity = read_validity(tmp_path / name)
        assert validity.end == openssl_end(tmp_path / name)
        assert validity.end - validity.start == timedelta(days=days)


def test_a_file_that_is_no_certificate_is_named(tmp_path: pathlib.Path) -> None:
    bundle = write_bundle(tmp_path)
    (tmp_path / "router.pem").write_text("not a certificate\n")
    with pytest.raises(BusConfigError) as raised:
        check_listen_certificate(load_config(bundle.router_config), datetime.now(UTC))
    assert raised.value.message.endswith(
        f"the router's certificate {tmp_path / 'router.pem'} cannot be read: "
        "no PEM certificate in it"
    )


def test_the_check_refuses_past_the_end_and_warns_before(
    tmp_path: pathlib.Path,
) -> None:
    """At the end date: refused; 10 days before: a warning; a year before: quiet."""
    config = load_config(write_bundle(tmp_path).router_config)
    end = read_validity(tmp_path / "router.pem").end
    with pytest.raises(BusConfigError) as raised:
        check_listen_certificate(config, end + timedelta(seconds=1))
    message = raised.value.message
    assert f"{tmp_path / 'router.pem'} expired on {end:%Y-%m-%d %H:%M} UTC" in message
    assert "rerun `armplan certs --out DIR` with the same --endpoint and --host" in (
        message
    )
    warning = check_listen_certificate(config, end - timedelta(days=10, hours=1))
    assert warning is not None and "(in 10 days)" in warning
    assert check_listen_certificate(config, end - timedelta(days=365)) is None


def test_the_router_refuses_an_expired_certificate(tmp_path: pathlib.Path) -> None:
    """Exit 1 at start, naming the file, the date and `armplan certs`."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    expire_router_certificate(tmp_path)
    router = Native(
        "router",
        ["python", "-m", catalog.ROUTER_MODULE, "--config", str(bundle.router_config)],
        tmp_path / "router.log",
    )
    try:
        code = router.process.wait(60)
    finally:
        router.stop()
    output = router.output()
    assert code == 1, output
    end = read_validity(tmp_path / "router.pem").end
    assert (
        f"router: Zenoh configuration {bundle.router_config} "
        f"(transport/link/tls/listen_certificate): the router's certificate "
        f"{tmp_path / 'router.pem'} expired on {end:%Y-%m-%d %H:%M} UTC"
    ) in output
    assert "router listening" not in output


def test_the_router_warns_of_a_certificate_near_its_end(
    tmp_path: pathlib.Path,
) -> None:
    """A certificate valid 10 days: the router listens, after a warning."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint(), days=10)
    router = Native(
        "router",
        ["python", "-m", catalog.ROUTER_MODULE, "--config", str(bundle.router_config)],
        tmp_path / "router.log",
    )
    try:
        deadline = time.monotonic() + 60
        while "router listening" not in router.output():
            assert router.running() and time.monotonic() < deadline, router.output()
            time.sleep(0.1)
    finally:
        router.stop()
    assert f"WARNING router: the router's certificate {tmp_path / 'router.pem'} " in (
        router.output()
    )
    assert "(in 9 days), and then no client accepts it: rerun `armplan certs" in (
        router.output()
    )


def test_certs_warns_of_a_kept_authority_near_or_past_its_end(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A CA of 10 days, then one expired: each rerun warns on stderr."""
    assert main(["certs", "--out", str(tmp_path), "--days", "10"]) == 0
    assert "warning" not in capsys.readouterr().err  # a new authority
    assert main(["certs", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert err.startswith(
        f"armplan certs: warning: the kept certificate authority "
        f"{tmp_path / 'ca.pem'} expires in 9 days, on "
    )
    assert "move ca.pem and ca.key out of the folder and rerun armplan certs" in err
    ca = str(tmp_path / "ca.pem")
    key = str(tmp_path / "ca.key")
    openssl(["x509", "-in", ca, "-signkey", key, "-days", "-1", "-out", ca])
    assert main(["certs", "--out", str(tmp_path)]) == 0
    end = read_validity(tmp_path / "ca.pem").end
    assert (
        f"{tmp_path / 'ca.pem'} expired on {end:%Y-%m-%d %H:%M} UTC"
        in capsys.readouterr().err
    )
