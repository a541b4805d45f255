"""A running router says when its certificate ends: a warning, then an ERROR.

The dates were checked only at start: a router whose certificate ended while
it ran logged nothing but Zenoh's "received fatal alert: CertificateExpired",
and every new client got the generic "no Zenoh router answers ... or refuses
this client". Now the router checks again hourly and at the end date itself,
and the client's message names an expired certificate among the causes. The
certificate that ends within seconds is issued by the real ``openssl ca``
(``-enddate``) from the bundle's own authority and key.
"""

from __future__ import annotations

import logging
import pathlib
import time
from datetime import UTC, datetime, timedelta

import pytest
from native_processes import Native

from armplan.launch import catalog, free_endpoint
from armplan.secure import write_bundle
from armplan.secure.certificates import ROUTER_COMMON_NAME, openssl
from shared.bus import Bus, load_config
from shared.bus.certificate_dates import read_validity
from shared.bus.certificate_watch import STILL_RUNNING, CertificateWatch
from shared.errors import ServiceUnavailableError

#: How long the router's certificate lasts after it is issued [s].
LIFETIME = 20.0
#: Longest wait for a line of the router's log [s].
LOG_WAIT = 60.0
_CA_CONFIG = """[ca]
default_ca = armplan
[armplan]
dir = {folder}
database = $dir/index.txt
new_certs_dir = $dir
serial = $dir/serial
default_md = sha256
policy = any
unique_subject = no
[any]
commonName = supplied
"""


def tls_endpoint() -> str:
    return "tls/127.0.0.1:" + free_endpoint().rsplit(":", 1)[1]


def issue_router_certificate_until(folder: pathlib.Path, end: datetime) -> None:
    """Reissue the bundle's router.pem from its key and CA, valid until ``end``."""
    scratch = folder / "ca-scratch"
    scratch.mkdir()
    (scratch / "index.txt").write_text("")
    (scratch / "serial").write_text("1000\n")
    (scratch / "ca.cnf").write_text(_CA_CONFIG.format(folder=scratch))
    (scratch / "router.ext").write_text(
        "subjectAltName=IP:127.0.0.1\nbasicConstraints=critical,CA:FALSE\n"
        "keyUsage=critical,digitalSignature,keyEncipherment\n"
        "extendedKeyUsage=serverAuth,clientAuth\n"
    )
    request = str(scratch / "router.csr")
    key = str(folder / "router.key")
    openssl(
        [
            *("req", "-new", "-key", key, "-out", request),
            *("-subj", f"/CN={ROUTER_COMMON_NAME}"),
        ]
    )
    start = datetime.now(UTC) - timedelta(hours=1)
    openssl(
        [
            *("ca", "-batch", "-config", str(scratch / "ca.cnf"), "-notext"),
            *("-cert", str(folder / "ca.pem"), "-keyfile", str(folder / "ca.key")),
            *("-in", request, "-out", str(folder / "router.pem")),
            *("-startdate", f"{start:%Y%m%d%H%M%SZ}"),
            *("-enddate", f"{end:%Y%m%d%H%M%SZ}"),
            *("-extfile", str(scratch / "router.ext")),
        ]
    )


def wait_for_line(router: Native, text: str) -> str:
    """The router's output once it holds ``text`` (fails after LOG_WAIT)."""
    deadline = time.monotonic() + LOG_WAIT
    while text not in router.output():
        assert router.running() and time.monotonic() < deadline, router.output()
        time.sleep(0.1)
    return router.output()


def test_the_watch_logs_each_problem_about_once_a_day(
    tmp_path: pathlib.Path, caplog: pytest.LogCaptureFixture
) -> None:
    """10 days before the end: a warning, not again within a day, again after;
    past the end: an ERROR at once, naming the file and the date."""
    write_bundle(tmp_path, days=40)
    path = tmp_path / "router.pem"
    validity = read_validity(path)
    watch = CertificateWatch(path, validity)
    caplog.set_level(logging.WARNING, logger="armplan.bus")
    watch.check(validity.end - timedelta(days=31))
    assert caplog.records == []
    for hours in (0, 1, 23, 24):
        watch.check(validity.end - timedelta(days=10) + timedelta(hours=hours))
    warnings = [r.getMessage() for r in caplog.records]
    assert len(warnings) == 2, warnings
    assert warnings[0].startswith(f"router: the router's certificate {path} expires ")
    assert "(in 10 days), and then no client accepts it" in warnings[0]
    assert "(in 9 days)" in warnings[1]
    caplog.clear()
    watch.check(validity.end + timedelta(seconds=1))
    watch.check(validity.end + timedelta(hours=1))
    [error] = caplog.records
    assert error.levelno == logging.ERROR
    assert error.getMessage() == (
        f"router: the router's certificate {path} expired on "
        f"{validity.end:%Y-%m-%d %H:%M} UTC: no client would accept it; rerun "
        "`armplan certs --out DIR` with the same --endpoint and --host options "
        "(the authority and the passwords are kept) and restart the router; "
        f"{STILL_RUNNING}"
    )


def test_the_watch_checks_at_the_end_date(tmp_path: pathlib.Path) -> None:
    """Hourly checks, and one just past the end date when that comes first."""
    write_bundle(tmp_path, days=40)
    validity = read_validity(tmp_path / "router.pem")
    watch = CertificateWatch(tmp_path / "router.pem", validity)
    assert watch.next_check(validity.end - timedelta(days=2), 3600) == 3600
    assert watch.next_check(validity.end - timedelta(seconds=90), 3600) == 91
    assert watch.next_check(validity.end + timedelta(seconds=5), 3600) == 3600


def test_a_running_router_logs_its_certificate_ending(tmp_path: pathlib.Path) -> None:
    """Hourly checks (the default), a certificate ending 20 s after it starts:
    an ERROR at the end naming the file, the router runs on, and a new client
    is refused with a message naming an expired certificate."""
    bundle = write_bundle(tmp_path, endpoint=tls_endpoint())
    end = datetime.now(UTC).replace(microsecond=0) + timedelta(seconds=LIFETIME)
    issue_router_certificate_until(tmp_path, end)
    assert read_validity(tmp_path / "router.pem").end == end
    router = Native(
        "router",
        ["python", "-m", catalog.ROUTER_MODULE, "--config", str(bundle.router_config)],
        tmp_path / "router.log",
    )
    client = load_config(bundle.clients["client"])
    try:
        started = wait_for_line(router, "router listening")
        assert "WARNING router: the router's certificate" in started
        assert "seconds), and then no client accepts it" in started
        with Bus.connect(client, wait=30) as before:
            output = wait_for_line(router, "ERROR router:")
            assert before.session.info.routers_zid()  # the open session goes on
        assert router.running()
        with pytest.raises(ServiceUnavailableError) as refused:
            Bus.connect(client).close()
    finally:
        router.stop()
    assert datetime.now(UTC) >= end
    assert (
        f"ERROR router: the router's certificate {tmp_path / 'router.pem'} expired "
        f"on {end:%Y-%m-%d %H:%M} UTC: no client would accept it"
    ) in output
    assert STILL_RUNNING in output
    assert "and not have expired: the router logs an ERROR then" in (
        refused.value.message
    )
