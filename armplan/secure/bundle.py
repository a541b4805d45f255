"""``armplan certs --out DIR``: a folder with everything a secured armplan needs.

What it writes (``DIR`` is where the files are made; the configurations name
them where the processes find them, ``paths``, by default ``DIR`` itself,
``/run/armplan/secure`` in docker-compose.secure.yml):

======================  ==================================================
``ca.pem``, ``ca.key``  the certificate authority (kept if present)
``router.pem``/``.key`` the router's certificate for ``hosts``, and its key
``passwords.txt``       one ``user:password`` line per user (users kept)
``router.json5``        ``config/secure/router.json5`` with the paths, the
                        endpoint and the routers to connect to set
``<user>.json5``        one client file per user of the access rules: the
                        router's endpoint, the CA, the user and its password
======================  ==================================================

Keys, passwords and client files are readable by their owner only, from
the moment they are created.

A run that fails changes nothing in ``DIR`` (a kept ``ca.key`` that does
not match ``ca.pem``, openssl failing, Ctrl-C): every file is first written
under a ``.partial`` name and renamed over the old one only once all of
them are written (``shared.output_paths.replaced_together``), so a rerun to
renew the router's certificate never leaves a router that cannot start.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

import zenoh

from armplan.secure.acl import AccessControl
from armplan.secure.certificates import (
    DAYS,
    MOST_DAYS,
    Authority,
    authority_warning,
    dropped_hosts_warning,
    issue_router_certificate,
    kept_authority,
    make_authority,
    subject_alt_names,
    tighten_key,
)
from armplan.secure.errors import SecureSetupError
from armplan.secure.passwords import (
    complete_passwords,
    passwords_text,
    read_passwords,
)
from armplan.secure.private_files import write_private
from shared.bus.certificate_dates import LISTEN_CERTIFICATE
from shared.bus.config import check_endpoint
from shared.bus.config_file import REPO_CONFIG, load_config
from shared.bus.keys import check_path
from shared.errors import InvalidInputError
from shared.output_paths import replaced_together

#: The secured router's configuration in the repository.
TEMPLATE = REPO_CONFIG.parent / "secure" / "router.json5"
#: Where the template's files live (the containers' folder).
TEMPLATE_PATHS = "/run/armplan/secure"
#: The template's endpoint (the compose router's).
TEMPLATE_ENDPOINT = "tls/router:7447"
#: The secured router's endpoint unless told (``armplan certs`` without --compose).
DEFAULT_ENDPOINT = "tls/127.0.0.1:7447"
#: The user other machines' routers log in with; it gets no client file.
ROUTER_USER = "router"
#: The template's namespace: its access rules name ``armplan/...`` keys.
TEMPLATE_NAMESPACE = "armplan"
#: The authority's files, made only if the folder holds none.
AUTHORITY_FILES = ("ca.key", "ca.pem")
#: The router's key and certificate, made anew by every run.
ROUTER_FILES = ("router.key", "router.pem")
#: The router's configuration and the password file.
ROUTER_CONFIG, PASSWORDS_FILE = "router.json5", "passwords.txt"


@dataclass(frozen=True)
class Bundle:
    """What :func:`write_bundle` wrote.

    Attributes:
        directory: The folder.
        router_config: The router's configuration file.
        clients: Each user's client configuration file.
        authority_created: Whether a new certificate authority was made.
        warnings: What the user should know, e.g. that the kept authority
            expires soon.
    """

    directory: Path
    router_config: Path
    clients: dict[str, Path]
    authority_created: bool
    warnings: tuple[str, ...] = ()


def write_bundle(
    directory: Path,
    *,
    endpoint: str = DEFAULT_ENDPOINT,
    hosts: Sequence[str] = (),
    paths: str | None = None,
    connect: Sequence[str] = (),
    days: int = DAYS,
    namespace: str = TEMPLATE_NAMESPACE,
) -> Bundle:
    """Write certificates, passwords and configurations into ``directory``.

    Args:
        directory: The folder (created if missing).
        endpoint: The router's TLS endpoint, e.g. ``tls/192.0.2.10:7447``.
        hosts: Names and addresses of the router's machine for its
            certificate (the endpoint's host and the loopback names are added).
        paths: Where the processes will find the files; default ``directory``;
            a relative path is made absolute against the current folder.
        connect: Other machines' routers this router connects to.
        days: Validity of new certificates [days], 1..``MOST_DAYS``.
        namespace: The key namespace of this deployment, e.g. ``"nao1"``: the
            access rules and every client file use it.

    Raises:
        SecureSetupError: a bad validity, endpoint, host or namespace (checked
            before anything is written), a folder that cannot be made, or
            openssl failing (nothing in ``directory`` is changed then).
        InvalidInputError: a file of the bundle cannot be written or replaced
            (nothing in ``directory`` is changed then).
    """
    _check_namespace(namespace)
    if not 1 <= days <= MOST_DAYS:
        raise SecureSetupError(
            f"certificates must be valid 1..{MOST_DAYS} days, got {days}"
        )
    for given in (endpoint, *connect):
        if not check_endpoint(given, "armplan certs").startswith("tls/"):
            raise SecureSetupError(
                f"endpoint {given!r} must use tls/, e.g. {DEFAULT_ENDPOINT}"
            )
    names = [*hosts, endpoint_host(endpoint), "localhost", "127.0.0.1"]
    subject_alt_names(names)  # a malformed host fails here, before any file
    make_folder(directory)
    where = str(directory.resolve()) if paths is None else absolute(paths)
    check_same_kind(directory, where)
    known = read_passwords(directory / "passwords.txt")  # a bad line: no file made
    access = AccessControl.from_file(TEMPLATE)
    passwords = complete_passwords(known, access.usernames())
    kept = kept_authority(directory)
    warnings = [] if kept is None else [authority_warning(kept, datetime.now(UTC))]
    warnings += [
        None if kept is None else tighten_key(kept.key),
        dropped_hosts_warning(directory / "router.pem", names),
    ]
    texts = bundle_texts(where, endpoint, connect, passwords, access, namespace)
    write_files(directory, kept, list(dict.fromkeys(names)), texts, days)
    clients = {
        user: directory / f"{user}.json5" for user in client_users(passwords, access)
    }
    said = tuple(w for w in warnings if w is not None)
    router_config = directory / ROUTER_CONFIG
    return Bundle(directory, router_config, clients, kept is None, said)


def write_files(
    directory: Path,
    kept: Authority | None,
    hosts: Sequence[str],
    texts: dict[str, str],
    days: int,
) -> None:
    """The certificates, keys and ``texts``, all or none (see the module docstring).

    Args:
        directory: The bundle's folder.
        kept: The authority found there, else ``None`` for a new one.
        hosts: What the router's certificate names.
        texts: The text files by name, each written owner-only.
        days: Validity of new certificates [days].

    Raises:
        SecureSetupError: openssl failed; it says nothing was changed.
    """
    made = [*(() if kept else AUTHORITY_FILES), *ROUTER_FILES, *texts]
    try:
        with replaced_together([directory / name for name in made]) as partials:
            staged = dict(zip(made, partials, strict=True))
            authority = kept or make_authority(staged["ca.pem"], staged["ca.key"], days)
            certificate, key = staged["router.pem"], staged["router.key"]
            issue_router_certificate(authority, hosts, certificate, key, days)
            for name, text in texts.items():
                write_private(staged[name], text)
    except SecureSetupError as error:
        raise SecureSetupError(
            f"{error.message}; nothing in {directory} was changed", path=error.path
        ) from None


def client_users(passwords: dict[str, str], access: AccessControl) -> list[str]:
    """The users that get a client file: every user of the rules but the router."""
    users = access.usernames()
    return [user for user in passwords if user != ROUTER_USER and user in users]


def bundle_texts(
    paths: str,
    endpoint: str,
    connect: Sequence[str],
    passwords: dict[str, str],
    access: AccessControl,
    namespace: str = TEMPLATE_NAMESPACE,
) -> dict[str, str]:
    """Every text file of the bundle by name: passwords, router and clients."""
    # with --connect the router's file holds the router's own password
    router = router_text(paths, endpoint, connect, passwords[ROUTER_USER], namespace)
    texts = {PASSWORDS_FILE: passwords_text(passwords), ROUTER_CONFIG: router}
    for user in client_users(passwords, access):
        client = client_text(paths, endpoint, user, passwords[user], namespace)
        texts[f"{user}.json5"] = client
    return texts


def make_folder(directory: Path) -> Path:
    """Make ``directory`` (and its parents); SecureSetupError naming it if not."""
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SecureSetupError(
            f"cannot make the folder {directory}: {exc.strerror}", path=str(directory)
        ) from None
    return directory


def absolute(paths: str) -> str:
    """``paths`` made absolute against the current folder (``..`` folded).

    The configurations name their files by these paths, and the processes
    that read them run in folders of their own: a relative path would be
    looked up from each one's.

    Raises:
        SecureSetupError: ``paths`` is empty.
    """
    if not paths.strip():
        raise SecureSetupError("--paths is empty: name the folder of the files")
    return paths if os.path.isabs(paths) else os.path.abspath(paths)


def bundle_kind(paths: str) -> str:
    """``"docker-compose"`` for the containers' folder, else ``"native"``."""
    return "docker-compose" if paths.rstrip("/") == TEMPLATE_PATHS else "native"


def existing_paths(directory: Path) -> str | None:
    """Where the files of the bundle already in ``directory`` are named, if any.

    Read from its ``router.json5`` (the folder of its router certificate).
    """
    try:
        config = zenoh.Config.from_json5((directory / "router.json5").read_text())
        named = json.loads(config.get_json(LISTEN_CERTIFICATE))
    except (OSError, zenoh.ZError, ValueError):
        return None
    return str(Path(named).parent) if isinstance(named, str) and named else None


def check_same_kind(directory: Path, paths: str) -> None:
    """Refuse to rewrite a native bundle as a docker-compose one, or back.

    Both rewrite every configuration in the folder (a compose bundle names
    its files in the containers' folder and the router ``tls/router:7447``),
    and the router's certificate is issued anew for the hosts of this run:
    README's two recipes, run into one folder, silently broke the first.

    Raises:
        SecureSetupError: naming both kinds and where to write instead.
    """
    before = existing_paths(directory)
    if before is None or bundle_kind(before) == bundle_kind(paths):
        return
    was, new = bundle_kind(before), bundle_kind(paths)
    raise SecureSetupError(
        f"{directory} holds a {was} bundle (its files named in {before}): this "
        f"run would rewrite it as a {new} bundle (files named in "
        f"{paths.rstrip('/')}) and reissue its router certificate. Write the "
        f"{new} bundle to a folder of its own (--out), or remove "
        f"{directory / 'router.json5'} to turn this one over",
        path=str(directory),
    )


def endpoint_host(endpoint: str) -> str:
    """The host of ``tls/HOST:PORT`` (brackets of an IPv6 address removed)."""
    host = endpoint.split("/", 1)[1].rsplit(":", 1)[0]
    return host.strip("[]")


def _check_namespace(namespace: str) -> None:
    try:
        check_path(namespace, "namespace")
    except InvalidInputError as error:
        raise SecureSetupError(error.message) from None


def router_text(
    paths: str,
    endpoint: str,
    connect: Sequence[str],
    router_password: str,
    namespace: str = TEMPLATE_NAMESPACE,
) -> str:
    """The template with its paths, endpoint, peer routers and namespace set.

    Another namespace replaces the template's in every key expression of the
    access rules (each is a quoted ``"armplan/..."``) and in the settings.
    """
    text = TEMPLATE.read_text()
    if namespace != TEMPLATE_NAMESPACE:
        text = text.replace(f'"{TEMPLATE_NAMESPACE}/', f'"{namespace}/')
        text = _replace_once(
            text,
            f'namespace: "{TEMPLATE_NAMESPACE}",',
            f"namespace: {json.dumps(namespace)},",
        )
    text = _replace_once(text, f'["{TEMPLATE_ENDPOINT}"]', json.dumps([endpoint]))
    if connect:
        peers = f"endpoints: {json.dumps(list(connect))},"
        text = _replace_once(text, "endpoints: [],", peers)
        login = f'user: "{ROUTER_USER}", password: {json.dumps(router_password)},'
        text = _replace_once(text, "usrpwd: {", "usrpwd: {\n        " + login)
    return text.replace(TEMPLATE_PATHS, paths.rstrip("/"))


def _replace_once(text: str, old: str, new: str) -> str:
    if text.count(old) != 1:
        raise SecureSetupError(
            f"{TEMPLATE} must hold {old!r} exactly once", path=str(TEMPLATE)
        )
    return text.replace(old, new)


def client_text(
    paths: str,
    endpoint: str,
    user: str,
    password: str,
    namespace: str = TEMPLATE_NAMESPACE,
) -> str:
    """One process's configuration: where the router is, the CA, its login."""
    client = {
        "transport/link/tls/root_ca_certificate": f"{paths.rstrip('/')}/ca.pem",
        "transport/auth/usrpwd/user": user,
        "transport/auth/usrpwd/password": password,
    }
    template = load_config(TEMPLATE)
    settings = {
        "namespace": namespace,
        "max_payload": template.max_payload,
        "timeout": template.timeout,
        "workers": template.workers,
        "queue_limit": template.queue_limit,
        "client": client,
    }
    body = {
        "mode": "client",
        "listen": {"endpoints": [endpoint]},
        "scouting": {"multicast": {"enabled": False}, "gossip": {"enabled": False}},
        "metadata": {"name": f"armplan-{user}", "armplan": settings},
    }
    header = (
        f"// armplan's Zenoh settings for user `{user}`, written by armplan certs.\n"
        "// `listen` is the router's endpoint: where this process connects.\n"
        "// It holds a password: keep it readable by its owner only.\n"
    )
    return header + json.dumps(body, indent=2) + "\n"
