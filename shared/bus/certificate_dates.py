"""When a TLS certificate is valid: read from its PEM file, checked at start.

A router whose certificate has expired still listens, and every client then
fails the handshake with a message that says nothing of the date (the
default validity, 825 days, ends a deployment after about 2.3 years).
:func:`check_listen_certificate` makes the router say so at start: it refuses
an expired certificate and warns of one that expires within
:data:`NEAR_EXPIRY_DAYS`. The dates are read from the certificate's DER
(``tbsCertificate.validity``, RFC 5280 section 4.1) by the few lines below:
the project's pinned dependencies hold no X.509 package.
"""

from __future__ import annotations

import base64
import binascii
import json
import re
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import NamedTuple

import zenoh

from shared.bus.config import BusConfig
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
_PEM = re.compile(
    rb"-----BEGIN CERTIFICATE-----(.+?)-----END CERTIFICATE-----", re.DOTALL
)
_SEQUENCE, _UTC_TIME, _GENERALIZED_TIME = 0x30, 0x17, 0x18


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
    found = _PEM.search(path.read_bytes())
    if found is None:
        raise ValueError("no PEM certificate in it")
    try:
        der = base64.b64decode(b"".join(found.group(1).split()), validate=True)
    except binascii.Error as error:
        raise ValueError(f"its PEM is not base64 ({error})") from None
    certificate = _content(der, 0, _SEQUENCE)[0]
    tbs = _content(der, certificate, _SEQUENCE)[0]
    field = tbs
    if der[field] == 0xA0:  # [0] version, present from version 2 on
        field = _skip(der, field)
    for _ in range(3):  # serial number, signature algorithm, issuer
        field = _skip(der, field)
    start, _ = _content(der, field, _SEQUENCE)
    end_at = _skip(der, start)
    return Validity(_time(der, start), _time(der, end_at))


def _header(der: bytes, at: int) -> tuple[int, int]:
    """Where the content of the DER element at ``at`` starts, and its length."""
    if at + 2 > len(der):
        raise ValueError("its DER is cut short")
    first = der[at + 1]
    if first < 0x80:
        return at + 2, first
    count = first & 0x7F
    if not 1 <= count <= 4 or at + 2 + count > len(der):
        raise ValueError("its DER has a malformed length")
    return at + 2 + count, int.from_bytes(der[at + 2 : at + 2 + count], "big")


def _content(der: bytes, at: int, tag: int) -> tuple[int, int]:
    """Start and end of the content of the element at ``at``, which has ``tag``."""
    if at >= len(der) or der[at] != tag:
        raise ValueError("its DER is not an X.509 certificate")
    start, length = _header(der, at)
    if start + length > len(der):
        raise ValueError("its DER is cut short")
    return start, start + length


def _skip(der: bytes, at: int) -> int:
    """Where the element after the one at ``at`` starts."""
    start, length = _header(der, at)
    return start + length


def _time(der: bytes, at: int) -> datetime:
    """The UTCTime or GeneralizedTime at ``at``."""
    tag = der[at] if at < len(der) else -1
    if tag not in (_UTC_TIME, _GENERALIZED_TIME):
        raise ValueError("its validity is not a time")
    start, end = _content(der, at, tag)
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
    path = listen_certificate(config)
    if path is None or not path.is_file():
        return None  # no TLS; a missing file is named where the files are checked
    try:
        validity = read_validity(path)
    except (OSError, ValueError) as error:
        raise BusConfigError(
            f"the router's certificate {path} cannot be read: {error}",
            source=config.source,
            setting=LISTEN_CERTIFICATE,
        ) from None
    if validity.end <= now:
        raise BusConfigError(
            f"the router's certificate {path} expired on {_day(validity.end)}: "
            f"no client would accept it; {RENEW}",
            source=config.source,
            setting=LISTEN_CERTIFICATE,
        )
    if validity.start > now:
        return (
            f"the router's certificate {path} is valid only from "
            f"{_day(validity.start)}: clients refuse it until then (is this "
            "machine's clock right?)"
        )
    if validity.end - now <= timedelta(days=NEAR_EXPIRY_DAYS):
        days = (validity.end - now).days
        return (
            f"the router's certificate {path} expires on {_day(validity.end)} "
            f"(in {days} days), and then no client accepts it: {RENEW}"
        )
    return None


def _day(when: datetime) -> str:
    """``when`` as ``2027-03-01 12:00 UTC``."""
    return when.strftime("%Y-%m-%d %H:%M UTC")
