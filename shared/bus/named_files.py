"""The files a Zenoh configuration names (TLS certificates, keys, passwords) exist.

A client whose CA file is gone (the bundle's folder moved: `armplan certs`
writes absolute paths) fails its handshake with the same message as a wrong
password or no router at all; a router whose key is gone said "is another
router using it?". Both now name the missing or unreadable file before Zenoh
is asked to open anything.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import zenoh

from shared.bus.config import BusConfig
from shared.errors import BusConfigError

#: The settings of a Zenoh configuration that name a file to read.
FILE_SETTINGS = (
    "transport/link/tls/root_ca_certificate",
    "transport/link/tls/listen_certificate",
    "transport/link/tls/listen_private_key",
    "transport/link/tls/connect_certificate",
    "transport/link/tls/connect_private_key",
    "transport/auth/usrpwd/dictionary_file",
)


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

    Args:
        config: The Zenoh configuration about to be opened.
        bus: The settings it was made from (for the file's name in errors).

    Raises:
        BusConfigError: naming the setting, the file and what is wrong.
    """
    for setting, path in named_files(config).items():
        problem = _problem(path)
        if problem is not None:
            raise BusConfigError(
                f"{path} {problem}", source=bus.source, setting=setting
            )


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
