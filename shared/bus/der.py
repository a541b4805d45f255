"""The few lines of DER (X.509's encoding) that armplan reads from certificates.

The dates of the router's certificate (``certificate_dates.py``) and whether a
client's CA file holds an authority (``ca_file.py``) are read from the
certificate's DER, RFC 5280 section 4.1: the project's pinned dependencies
hold no X.509 package. Positions are byte offsets into ``der``.
"""

from __future__ import annotations

import base64
import binascii
import re

#: Tags of the DER elements read here.
BOOLEAN, OCTET_STRING, OID, SEQUENCE = 0x01, 0x04, 0x06, 0x30
_PEM = re.compile(
    rb"-----BEGIN CERTIFICATE-----(.+?)-----END CERTIFICATE-----", re.DOTALL
)


def pem_certificates(data: bytes) -> list[bytes]:
    """The DER of each PEM certificate in ``data``, in order ([] if none).

    Raises:
        ValueError: if a PEM block is not base64.
    """
    found = []
    for block in _PEM.finditer(data):
        try:
            text = b"".join(block.group(1).split())
            found.append(base64.b64decode(text, validate=True))
        except binascii.Error as error:
            raise ValueError(f"its PEM is not base64 ({error})") from None
    return found


def tbs_fields(der: bytes) -> list[int]:
    """Where each field of the certificate's ``tbsCertificate`` starts.

    Version 1 certificates have no ``[0]`` version field: the list then
    starts with the serial number.

    Raises:
        ValueError: if ``der`` is not an X.509 certificate.
    """
    certificate = content(der, 0, SEQUENCE)[0]
    return children(der, *content(der, certificate, SEQUENCE))


def children(der: bytes, start: int, end: int) -> list[int]:
    """Where each element between ``start`` and ``end`` starts."""
    found = []
    while start < end:
        found.append(start)
        start = skip(der, start)
    if start != end:
        raise ValueError("its DER is cut short")
    return found


def content(der: bytes, at: int, tag: int) -> tuple[int, int]:
    """Start and end of the content of the element at ``at``, which has ``tag``."""
    if at >= len(der) or der[at] != tag:
        raise ValueError("its DER is not an X.509 certificate")
    start, length = _header(der, at)
    if start + length > len(der):
        raise ValueError("its DER is cut short")
    return start, start + length


def skip(der: bytes, at: int) -> int:
    """Where the element after the one at ``at`` starts."""
    start, length = _header(der, at)
    return start + length


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
