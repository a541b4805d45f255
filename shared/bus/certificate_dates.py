"""When a TLS certificate is valid: read from its PEM file, checked at start.

A router whose certificate has expired still listens, and every client then
fails the handshake with a message that says nothing of the date (the
default validity, 825 days, ends a deployment after about 2.3 years).
:func:`check_listen_certificate` makes the router say so at start: it refuses
an expired certificate and warns of one that expires within
:data:`NEAR_EXPIRY_DAYS` (``certificate_watch.py`` checks again while it
runs). The dates are read from the certificate's DER
(``tbsCertificate.validity``, RFC 5280 section 4.1) with ``der.py``: the
project's pinned dependencies hold no X.509 package.
"""

from __future__ import annotations

import json
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import NamedTuple

import zenoh

from shared.bus.config import BusConfig
from shared.bus.der import SEQUENCE, content, pem_certificates, skip, tbs_fields
from shared.bus.zenoh_config import router_config
from shared.errors import BusConfigError

#: A certificate that expires within this many days is warned about [days].
NEAR_EXPIRY_DAYS = 30
#: Where a router's configuration names its certificate.
LISTEN_CERTIFICATE = "transport/link/tls/listen_certificate"
#: What to do about a certificate near or past its end.
RENEW = (
    "rerun `armplan certs --out DIR` with the same --endpoint and --host options "
    "(the authority and the passwords are kept) and restart the router"
)
_VERSION, _UTC_TIME, _GENERALIZED_TIME = 0xA0, 0x17, 0x18


class Validity(NamedTuple):
    """A certificate's validity period (UTC)."""

    start: datetime
    end: datetime


def read_validity(path: Path) -> Validity:
    """The validity of the first certificate in the PEM file at ``path``.

    Raises:
        OSError: if the file cannot be read.
        ValueError: if it holds no well-formed certificate.
    """
    found = pem_certificates(path.read_bytes())
    if not found:
        raise ValueError("no PEM certificate in it")
    der = found[0]
    fields = tbs_fields(der)
    version = 1 if der[fields[0]] == _VERSION else 0  # present from version 2 on
    if len(fields) < version + 5:
        raise ValueError("its DER is not an X.509 certificate")
    # serial number, signature algorithm, issuer, then the validity
    start = content(der, fields[version + 3], SEQUENCE)[0]
    return Validity(_time(der, start), _time(der, skip(der, start)))


def _time(der: bytes, at: int) -> datetime:
    """The UTCTime or GeneralizedTime at ``at``."""
    tag = der[at] if at < len(der) else -1
    if tag not in (_UTC_TIME, _GENERALIZED_TIME):
        raise ValueError("its validity is not a time")
    start, end = content(der, at, tag)
    text = der[start:end].decode("ascii", errors="replace")
    layout = "%y%m%d%H%M%SZ" if tag == _UTC_TIME else "%Y%m%d%H%M%SZ"
    try:
        return datetime.strptime(text, layout).replace(tzinfo=UTC)
    except ValueError:
        raise ValueError(f"its validity time {text!r} is malformed") from None


def listen_certificate(config: BusConfig) -> Path | None:
    """The certificate the router's configuration names, ``None`` if none."""
    try:
        named = json.loads(router_config(config).get_json(LISTEN_CERTIFICATE))
    except zenoh.ZError:
        return None
    return Path(named) if isinstance(named, str) and named else None


class DateProblem(NamedTuple):
    """What is wrong with a certificate's dates at some time.

    Attributes:
        kind: ``"early"`` (not valid yet), ``"ending"`` (within
            :data:`NEAR_EXPIRY_DAYS`) or ``"expired"``.
        message: What to tell, naming the file and the date.
    """

    kind: str
    message: str


def listen_validity(config: BusConfig) -> tuple[Path, Validity] | None:
    """The router's certificate and its validity, ``None`` without one.

    Raises:
        BusConfigError: naming the file if it cannot be read as a certificate.
    """
    path = listen_certificate(config)
    if path is None or not path.is_file():
        return None  # no TLS; a missing file is named where the files are checked
    try:
        return path, read_validity(path)
    except (OSError, ValueError) as error:
        raise BusConfigError(
            f"the router's certificate {path} cannot be read: {error}",
            source=config.source,
            setting=LISTEN_CERTIFICATE,
        ) from None


def date_problem(path: Path, validity: Validity, now: datetime) -> DateProblem | None:
    """What is wrong with the router's certificate at ``path`` at ``now`` (UTC).

    ``None`` if it is valid and ends more than :data:`NEAR_EXPIRY_DAYS` later.
    """
    if validity.end <= now:
        return DateProblem(
            "expired",
            f"the router's certificate {path} expired on {_day(validity.end)}: "
            f"no client would accept it; {RENEW}",
        )
    if validity.start > now:
        return DateProblem(
            "early",
            f"the router's certificate {path} is valid only from "
            f"{_day(validity.start)}: clients refuse it until then (is this "
            "machine's clock right?)",
        )
    if validity.end - now <= timedelta(days=NEAR_EXPIRY_DAYS):
        return DateProblem(
            "ending",
            f"the router's certificate {path} expires on {_day(validity.end)} "
            f"(in {_left(validity.end - now)}), and then no client accepts it: "
            f"{RENEW}",
        )
    return None


def check_listen_certificate(config: BusConfig, now: datetime) -> str | None:
    """Refuse the router's expired certificate; a warning if it expires soon.

    Args:
        config: The router's settings.
        now: The current time (UTC).

    Returns:
        A warning for a certificate not valid yet or ending within
        :data:`NEAR_EXPIRY_DAYS`, else ``None`` (also with no certificate).

    Raises:
        BusConfigError: naming the file and its end date if it has expired or
            cannot be read as a certificate.
    """
    found = listen_validity(config)
    problem = None if found is None else date_problem(*found, now)
    if problem is None:
        return None
    if problem.kind == "expired":
        raise BusConfigError(
            problem.message, source=config.source, setting=LISTEN_CERTIFICATE
        )
    return problem.message


def _left(time: timedelta) -> str:
    """``time`` in whole days, else hours, minutes or seconds: ``9 days``."""
    seconds = int(time.total_seconds())
    for unit, length in (("day", 86_400), ("hour", 3600), ("minute", 60)):
        if seconds >= length:
            count = seconds // length
            return f"{count} {unit}{'s' if count != 1 else ''}"
    return f"{seconds} second{'s' if seconds != 1 else ''}"


def _day(when: datetime) -> str:
    """``when`` as ``2027-03-01 12:00 UTC``."""
    return when.strftime("%Y-%m-%d %H:%M UTC")
