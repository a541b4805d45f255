"""A certificate authority and the router's TLS certificate, made with ``openssl``.

Every armplan process trusts the authority (``ca.pem``) and checks that the
router's certificate (``router.pem``) names the host it connects to: the
certificate lists every name and address of the router's machine given with
``--host`` (``subjectAltName``). Keys are EC P-256, readable by their owner
only. An existing authority is kept, so a second machine's router gets a
certificate from the same authority. ``openssl`` is used rather than a Python
package because the project's pinned dependencies hold none for X.509.
"""

from __future__ import annotations

import ipaddress
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from datetime import datetime, timedelta
from pathlib import Path
from typing import NamedTuple

from armplan.secure.errors import SecureSetupError
from armplan.secure.private_files import create_private
from shared.bus.certificate_dates import NEAR_EXPIRY_DAYS, read_validity

#: Validity of the certificates [days].
DAYS = 825
#: Longest validity a certificate may be given [days] (100 years).
MOST_DAYS = 36_500
#: Every router certificate's common name: the access rules know a router a
#: router connects to by it (the names it is reached by are its alt names).
ROUTER_COMMON_NAME = "armplan router"
_HOSTNAME = re.compile(
    r"^(?=.{1,253}$)[A-Za-z0-9]([A-Za-z0-9-]{0,61}[A-Za-z0-9])?"
    r"(\.[A-Za-z0-9]([A-Za-z0-9-]{0,61}[A-Za-z0-9])?)*$"
)
_KEY = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256", "-nodes"]


class Authority(NamedTuple):
    """The certificate authority's files and whether this run created them."""

    certificate: Path
    key: Path
    created: bool


def check_host(host: str) -> str:
    """``host`` if it is a DNS name or an IP address; else SecureSetupError."""
    try:
        ipaddress.ip_address(host)
    except ValueError:
        # a last label all digits is no DNS name (RFC 3696, 2): 999.1.1.1 is
        # a mistyped address, which no client's name would ever match
        if not _HOSTNAME.match(host) or host.rsplit(".", 1)[-1].isdigit():
            raise SecureSetupError(
                f"host {host!r} is neither a DNS name nor an IP address"
            ) from None
    return host


def subject_alt_names(hosts: Sequence[str]) -> str:
    """The ``subjectAltName`` value, e.g. ``DNS:router,IP:127.0.0.1``."""
    names = []
    for host in dict.fromkeys(map(check_host, hosts)):
        try:
            ipaddress.ip_address(host)
            names.append(f"IP:{host}")
        except ValueError:
            names.append(f"DNS:{host}")
    return ",".join(names)


def kept_authority(directory: Path) -> Authority | None:
    """``ca.pem`` and ``ca.key`` in ``directory`` if both exist, else ``None``.

    Raises:
        SecureSetupError: if only one of the two exists (a copied bundle
            without the key): a new authority would replace the one every
            other machine trusts.
    """
    certificate, key = directory / "ca.pem", directory / "ca.key"
    if certificate.is_file() and key.is_file():
        return Authority(certificate, key, created=False)
    check_no_half_authority(certificate, key)
    return None


def make_authority(certificate: Path, key: Path, days: int = DAYS) -> Authority:
    """A new authority, written to ``certificate`` and ``key`` (owner-only).

    Raises:
        SecureSetupError: if ``openssl`` fails.
    """
    create_private(key)  # openssl writes into it and keeps its mode
    openssl(
        [
            *("req", "-x509", *_KEY, "-keyout", str(key), "-out", str(certificate)),
            *("-days", str(days), "-subj", "/CN=armplan certificate authority"),
            *("-addext", "basicConstraints=critical,CA:TRUE"),
            *("-addext", "keyUsage=critical,keyCertSign,cRLSign"),
        ]
    )
    return Authority(certificate, key, created=True)


def tighten_key(key: Path) -> str | None:
    """Make a kept key readable by its owner only; what was done, or ``None``.

    Returns:
        A warning if the key was open to others: tightened to 0600, or, if
        this user may not change it, left as it was.
    """
    mode = key.stat().st_mode & 0o777
    if not mode & 0o077:
        return None
    try:
        os.chmod(key, 0o600)
    except PermissionError:
        return (
            f"{key} is readable by others (mode {mode:04o}) and this user may not "
            f"change it: make it owner-only (chmod 600 {key})"
        )
    return (
        f"{key} was readable by others (mode {mode:04o}): made owner-only (0600); "
        "if others could read it, anyone with it can sign a router certificate"
    )


def check_no_half_authority(certificate: Path, key: Path) -> None:
    """Refuse to make a new authority over half of an existing one.

    A second machine's folder holds ``ca.pem`` without ``ca.key`` (the key
    stays where the bundles are made): rerunning ``armplan certs`` there made
    a new authority, and that machine no longer trusted the others' routers.

    Raises:
        SecureSetupError: naming the file that is there and the one missing,
            or the one that is not a file (a folder ``ca.pem`` was "ca.pem
            exists without ca.key", with ca.key beside it).
    """
    for path in (certificate, key):
        if path.exists() and not path.is_file():
            raise SecureSetupError(
                f"{path} is not a file (a folder?): it must be the authority's "
                f"{'certificate' if path == certificate else 'key'}; remove it "
                "or give another --out",
                path=str(path),
            )
    if certificate.exists() and not key.exists():
        raise SecureSetupError(
            f"{certificate} exists without {key.name}: its key is needed to sign "
            f"the router's certificate. Copy {key.name} here (or make this "
            "bundle on the machine that holds it and copy the bundle), or remove "
            f"{certificate.name} to make a new authority (every machine then "
            "needs the new one)",
            path=str(certificate),
        )
    if key.exists() and not certificate.exists():
        raise SecureSetupError(
            f"{key} exists without {certificate.name}: copy {certificate.name} "
            f"here, or remove {key.name} to make a new authority",
            path=str(key),
        )


def authority_warning(authority: Authority, now: datetime) -> str | None:
    """A warning if a kept authority has expired or expires soon, else ``None``.

    Args:
        authority: The authority :func:`kept_authority` returned.
        now: The current time (UTC).

    Raises:
        SecureSetupError: if the kept ``ca.pem`` is not a certificate.
    """
    if authority.created:
        return None
    try:
        end = read_validity(authority.certificate).end
    except (OSError, ValueError) as error:
        raise SecureSetupError(
            f"{authority.certificate} is not a readable certificate: {error}",
            path=str(authority.certificate),
        ) from None
    if end > now + timedelta(days=NEAR_EXPIRY_DAYS):
        return None
    when = end.strftime("%Y-%m-%d %H:%M UTC")
    state = "expired on" if end <= now else f"expires in {(end - now).days} days, on"
    return (
        f"the kept certificate authority {authority.certificate} {state} {when}; "
        "for a new one, move ca.pem and ca.key out of the folder and rerun armplan "
        "certs, then give every machine its new bundle (each needs the new ca.pem)"
    )


def certificate_hosts(certificate: Path) -> list[str]:
    """The DNS names and IP addresses a certificate names, [] if unreadable."""
    binary = shutil.which("openssl")
    if binary is None or not certificate.is_file():
        return []
    shown = subprocess.run(
        [binary, "x509", "-in", str(certificate), "-noout", "-ext", "subjectAltName"],
        capture_output=True,
        text=True,
        check=False,
    )
    found = re.findall(r"(?:DNS|IP Address):([^,\s]+)", shown.stdout)
    return [_normal(h) for h in found]


def _normal(host: str) -> str:
    """An address in its short form (``::1``), a DNS name in lower case."""
    try:
        return str(ipaddress.ip_address(host))
    except ValueError:
        return host.lower()


def dropped_hosts_warning(certificate: Path, hosts: Sequence[str]) -> str | None:
    """A warning if the router's current certificate names hosts ``hosts`` lacks.

    Each run issues the certificate for its own ``--host`` names only: a
    machine reached by a name given before, and not again, would be refused.
    """
    wanted = {_normal(h) for h in hosts}
    dropped = [h for h in certificate_hosts(certificate) if h not in wanted]
    if not dropped:
        return None
    return (
        f"{certificate} named {', '.join(dropped)}, which the new one does not: "
        "clients reaching the router by those names will be refused; give them "
        "again with --host to keep them"
    )


def issue_router_certificate(
    authority: Authority,
    hosts: Sequence[str],
    certificate: Path,
    key: Path,
    days: int = DAYS,
) -> None:
    """Write the router's certificate, signed by ``authority``, naming ``hosts``.

    Args:
        authority: The authority that signs it.
        hosts: The names and addresses the certificate names.
        certificate: The file to write the certificate to.
        key: The file to write its new key to (made owner-only first).
        days: Validity [days].

    The signing request and the other scratch files of ``openssl`` go to a
    temporary folder of their own, never beside ``certificate``.

    Raises:
        SecureSetupError: if a host is malformed or ``openssl`` fails.
    """
    if not hosts:
        raise SecureSetupError("the router's certificate needs at least one host")
    create_private(key)  # openssl writes into it and keeps its mode
    with tempfile.TemporaryDirectory(prefix="armplan-certs-") as scratch:
        request, extensions = Path(scratch, "router.csr"), Path(scratch, "router.ext")
        extensions.write_text(
            f"subjectAltName={subject_alt_names(hosts)}\n"
            "basicConstraints=critical,CA:FALSE\n"
            "keyUsage=critical,digitalSignature,keyEncipherment\n"
            "extendedKeyUsage=serverAuth,clientAuth\n"
        )
        openssl(
            [
                *("req", *_KEY, "-keyout", str(key), "-out", str(request)),
                *("-subj", f"/CN={ROUTER_COMMON_NAME}"),
            ]
        )
        openssl(
            [
                *("x509", "-req", "-in", str(request)),
                *("-CA", str(authority.certificate), "-CAkey", str(authority.key)),
                *("-CAserial", str(Path(scratch, "ca.srl")), "-CAcreateserial"),
                *("-out", str(certificate), "-days", str(days)),
                *("-extfile", str(extensions)),
            ]
        )


def openssl(args: Sequence[str]) -> None:
    """Run ``openssl ARGS``; SecureSetupError with its message if it fails."""
    binary = shutil.which("openssl")
    if binary is None:
        raise SecureSetupError(
            "the openssl command is needed to make certificates and was not found "
            "(install it, e.g. the distribution's openssl package)"
        )
    done = subprocess.run(
        [binary, *args], capture_output=True, text=True, timeout=60, check=False
    )
    if done.returncode != 0:
        problem = " ".join(done.stderr.split())[-400:]
        raise SecureSetupError(f"openssl {args[0]} failed: {problem}")
