"""The files a Zenoh configuration names (TLS certificates, keys, passwords) exist.

A client whose CA file is gone (the bundle's folder moved: `armplan certs`
writes absolute paths) fails its handshake with the same message as a wrong
password or no router at all; a router whose key is gone said "is another
router using it?". Both now name the missing or unreadable file before Zenoh
is asked to open anything, and a CA file that holds no authority
(``ca_file.py``). A key or a password that other users may read is warned
about (``armplan certs`` writes them owner-only; a copy may not keep that);
one that another user owns (a key root shares with a service's group) may
also be read by its group (:func:`open_to_others`).
"""

from __future__ import annotations

import grp
import json
import logging
import os
import pwd
from pathlib import Path

import zenoh

from shared.bus.ca_file import ca_file_problem
from shared.bus.config import BusConfig
from shared.errors import BusConfigError

log = logging.getLogger("armplan.bus")

#: The settings of a Zenoh configuration that name a file to read.
FILE_SETTINGS = (
    "transport/link/tls/root_ca_certificate",
    "transport/link/tls/listen_certificate",
    "transport/link/tls/listen_private_key",
    "transport/link/tls/connect_certificate",
    "transport/link/tls/connect_private_key",
    "transport/auth/usrpwd/dictionary_file",
)
#: The setting naming the certificate authority a TLS link trusts.
CA_SETTING = "transport/link/tls/root_ca_certificate"
#: Settings naming a file only its owner may read, and what the file holds.
SECRET_FILES = {
    "transport/link/tls/listen_private_key": "a private key",
    "transport/link/tls/connect_private_key": "a private key",
    "transport/auth/usrpwd/dictionary_file": "every user's password",
}


def named_files(config: zenoh.Config) -> dict[str, Path]:
    """Each file setting of ``config`` that is set, and the file it names."""
    found = {}
    for setting in FILE_SETTINGS:
        try:
            value = json.loads(config.get_json(setting))
        except zenoh.ZError:
            continue
        if isinstance(value, str) and value:
            found[setting] = Path(value)
    return found


def check_named_files(config: zenoh.Config, bus: BusConfig) -> None:
    """Refuse a configuration naming a file that is missing or unreadable.

    Also refuses a CA file that holds no certificate authority, and logs a
    warning for each key or password file (the configuration file itself if
    it holds a password) that other users may read.

    Args:
        config: The Zenoh configuration about to be opened.
        bus: The settings it was made from (for the file's name in errors).

    Raises:
        BusConfigError: naming the setting, the file and what is wrong.
    """
    for setting, path in named_files(config).items():
        problem = _problem(path)
        if problem is None and setting == CA_SETTING:
            problem = ca_file_problem(path)
        if problem is not None:
            raise BusConfigError(
                f"{path} {problem}", source=bus.source, setting=setting
            )
    for path, held in _secret_files(config, bus).items():
        warning = open_to_others(path, held)
        if warning is not None:
            log.warning("%s", warning)


def open_to_others(path: Path, held: str) -> str | None:
    """A warning if users it should not trust may open ``path``, else ``None``.

    A file this process's user owns must be owner-only (0600). A file
    another user owns, e.g. a key owned by root with group ``ssl-cert`` and
    mode 0640 that a service reads as a member of that group, may also be
    read by its group (PostgreSQL's rule for a root-owned key): only write
    or execute by the group, or any access by others, is warned about there.
    ``chmod 600`` would lock the service out of such a file.

    Args:
        path: The file.
        held: What it holds, e.g. ``"a private key"``.
    """
    try:
        status = path.stat()
    except OSError:
        return None
    mode = status.st_mode & 0o777
    owner = _user_name(status.st_uid)
    if status.st_uid == os.geteuid():
        if not mode & 0o077:
            return None
        return (
            f"{path} holds {held} and is open to other users (mode {mode:04o}, "
            f"owner {owner}): make it readable by its owner only: chmod 600 {path}"
        )
    if not mode & 0o037:
        return None
    group = _group_name(status.st_gid)
    return (
        f"{path} holds {held} and is open to other users (mode {mode:04o}, owner "
        f"{owner}, group {group}): make it readable by its owner and group only "
        f"(this process's user in group {group}): chmod 640 {path}, as {owner}"
    )


def _user_name(uid: int) -> str:
    """The user's name, or its number if the system knows no name for it."""
    try:
        return pwd.getpwuid(uid).pw_name
    except KeyError:
        return f"uid {uid}"


def _group_name(gid: int) -> str:
    """The group's name, or its number if the system knows no name for it."""
    try:
        return grp.getgrgid(gid).gr_name
    except KeyError:
        return f"gid {gid}"


def _secret_files(config: zenoh.Config, bus: BusConfig) -> dict[Path, str]:
    """The files of ``config`` only their owner may read, and what each holds."""
    named = named_files(config)
    found = {named[s]: held for s, held in SECRET_FILES.items() if s in named}
    try:
        password = json.loads(config.get_json("transport/auth/usrpwd/password"))
    except zenoh.ZError:
        password = None
    source = Path(bus.source)
    if password and source.is_file():
        found[source] = "a password"
    return found


def _problem(path: Path) -> str | None:
    """What is wrong with the file at ``path`` for this process, or ``None``."""
    relative = "" if path.is_absolute() else f" (relative to {Path.cwd()})"
    if not path.exists():
        return (
            f"does not exist{relative}: was the folder moved? Rerun `armplan "
            "certs --out DIR` where the files are now (or give --paths), or "
            "correct the path"
        )
    if not path.is_file():
        return f"is not a file{relative}"
    if not os.access(path, os.R_OK):
        return (
            f"cannot be read by this process's user (uid {os.getuid()}){relative}: "
            "the files are readable by their owner only"
        )
    return None
