"""A CA file holds a certificate authority: checked before a TLS session opens.

A client whose ``root_ca_certificate`` was empty, not PEM, or the router's
own certificate (``router.pem`` for ``ca.pem``) failed its handshake with the
generic "no Zenoh router answers ... or one answers but refuses this client".
:func:`ca_file_problem` names what is wrong with the file instead. A
self-signed certificate is a trust anchor whatever its basicConstraints: the
usual way to trust a self-signed router is to name its own certificate, and
rustls takes a self-signed server certificate only when marked ``CA:FALSE``.
The certificates are read with ``der.py`` (the pinned dependencies hold no
X.509 package).
"""

from __future__ import annotations

from pathlib import Path

from shared.bus.der import (
    BOOLEAN,
    OCTET_STRING,
    OID,
    SEQUENCE,
    children,
    content,
    pem_certificates,
    tbs_fields,
)

#: DER of the object identifier of basicConstraints, 2.5.29.19 (RFC 5280).
BASIC_CONSTRAINTS = bytes([0x55, 0x1D, 0x13])
#: What a CA file should be, for the messages.
WANTED = "give the authority's certificate (ca.pem of `armplan certs`)"
_EXTENSIONS, _VERSION = 0xA3, 0xA0


def ca_file_problem(path: Path) -> str | None:
    """What keeps the file at ``path`` from being a CA file, or ``None``.

    It must hold at least one PEM certificate TLS may trust as given: one
    whose basicConstraints says ``CA:TRUE``, or that has none (an old
    version 1 authority), or a self-signed one (whatever its
    basicConstraints). Only certificates marked ``CA:FALSE`` and issued by
    another (``router.pem`` of ``armplan certs``) are refused.
    """
    try:
        certificates = pem_certificates(path.read_bytes())
        if not certificates:
            return f"holds no PEM certificate (-----BEGIN CERTIFICATE-----): {WANTED}"
        if not any(is_self_signed(c) or is_authority(c) for c in certificates):
            return (
                "holds no certificate authority, only certificates marked "
                "CA:FALSE that another issued (is it the router's "
                f"certificate?): {WANTED}"
            )
    except (OSError, ValueError) as error:
        return f"cannot be read as a certificate ({error}): {WANTED}"
    return None


def is_authority(der: bytes) -> bool:
    """Whether the certificate may sign others (no basicConstraints CA:FALSE).

    Raises:
        ValueError: if ``der`` is not an X.509 certificate.
    """
    extensions = [at for at in tbs_fields(der) if der[at] == _EXTENSIONS]
    if not extensions:
        return True
    listed = content(der, extensions[0], _EXTENSIONS)[0]
    for extension in children(der, *content(der, listed, SEQUENCE)):
        parts = children(der, *content(der, extension, SEQUENCE))
        start, end = content(der, parts[0], OID)
        if der[start:end] == BASIC_CONSTRAINTS:
            return _says_authority(der, content(der, parts[-1], OCTET_STRING)[0])
    return True


def is_self_signed(der: bytes) -> bool:
    """Whether the certificate names itself as its issuer (issuer == subject).

    The names are compared as encoded, as a self-signed certificate made by
    openssl or ``armplan certs`` repeats the subject's bytes as its issuer.

    Raises:
        ValueError: if ``der`` is not an X.509 certificate.
    """
    fields = tbs_fields(der)
    version = 1 if der[fields[0]] == _VERSION else 0  # present from version 2 on
    if len(fields) < version + 6:
        raise ValueError("its DER is not an X.509 certificate")
    # serial number, signature algorithm, issuer, validity, subject
    issuer, subject = fields[version + 2], fields[version + 4]
    return der[issuer : fields[version + 3]] == der[subject : fields[version + 5]]


def _says_authority(der: bytes, at: int) -> bool:
    """Whether the BasicConstraints at ``at`` holds ``cA`` TRUE (default FALSE)."""
    fields = children(der, *content(der, at, SEQUENCE))
    if not fields or der[fields[0]] != BOOLEAN:
        return False
    start, end = content(der, fields[0], BOOLEAN)
    return end > start and der[start] != 0
