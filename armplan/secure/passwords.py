"""One random password per user, in Zenoh's user/password dictionary file.

The router reads the file (``transport/auth/usrpwd/dictionary_file``): one
``user:password`` line per user. Each process logs in with its own user and
password (``transport/auth/usrpwd/user`` and ``password`` in its client
file). Users already in the file keep their passwords, so the file can be
copied to a second machine and completed there.
"""

from __future__ import annotations

import os
import re
import secrets
from collections.abc import Iterable
from pathlib import Path

from armplan.secure.errors import SecureSetupError

#: Random bytes per password (URL-safe base64: about 32 characters).
PASSWORD_BYTES = 24
_USER = re.compile(r"^[a-z][a-z0-9_-]*$")


def read_passwords(path: Path) -> dict[str, str]:
    """The ``user:password`` lines of ``path`` (empty if it does not exist).

    Raises:
        SecureSetupError: naming the line that is not ``user:password``.
    """
    if not path.is_file():
        return {}
    passwords = {}
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        user, colon, password = line.partition(":")
        if not line.strip():
            continue
        if not colon or not _USER.match(user) or not password:
            raise SecureSetupError(
                f"{path} line {number} is not user:password", path=str(path)
            )
        passwords[user] = password
    return passwords


def ensure_passwords(path: Path, users: Iterable[str]) -> dict[str, str]:
    """Every user of ``users`` in the file at ``path``, new ones with new passwords.

    Returns:
        Every user's password, those already in the file included.
    """
    passwords = read_passwords(path)
    for user in users:
        if not _USER.match(user):
            raise SecureSetupError(f"user name {user!r} must match {_USER.pattern}")
        passwords.setdefault(user, secrets.token_urlsafe(PASSWORD_BYTES))
    write_private(path, "".join(f"{u}:{p}\n" for u, p in passwords.items()))
    return passwords


def write_private(path: Path, text: str) -> None:
    """Write ``text`` to ``path``, readable and writable by its owner only."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(descriptor, "w") as file:
        file.write(text)
    os.chmod(path, 0o600)
