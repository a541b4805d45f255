"""One random password per user, in Zenoh's user/password dictionary file.

The router reads the file (``transport/auth/usrpwd/dictionary_file``): one
``user:password`` line per user. Each process logs in with its own user and
password (``transport/auth/usrpwd/user`` and ``password`` in its client
file). Users already in the file keep their passwords, so the file can be
copied to a second machine and completed there.
"""

from __future__ import annotations

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
        SecureSetupError: naming the line that is not ``user:password``, or
            the file when it cannot be read or is not UTF-8 text.
    """
    if not path.is_file():
        return {}
    passwords = {}
    for number, line in enumerate(_text(path).splitlines(), start=1):
        user, colon, password = line.partition(":")
        if not line.strip():
            continue
        if not colon or not _USER.match(user) or not password:
            raise SecureSetupError(
                f"{path} line {number} is not user:password", path=str(path)
            )
        passwords[user] = password
    return passwords


def _text(path: Path) -> str:
    """The file's text; a file saved as UTF-16 ended in a traceback."""
    try:
        return path.read_bytes().decode()
    except OSError as error:
        raise SecureSetupError(
            f"cannot read {path}: {error.strerror}", path=str(path)
        ) from None
    except UnicodeDecodeError as error:
        raise SecureSetupError(
            f"{path} is not UTF-8 text (byte {error.start}): it must hold "
            "user:password lines",
            path=str(path),
        ) from None


def complete_passwords(known: dict[str, str], users: Iterable[str]) -> dict[str, str]:
    """``known`` with a new random password for each user of ``users`` it lacks.

    Returns:
        Every user's password, those already known first, unchanged.
    """
    passwords = dict(known)
    for user in users:
        if not _USER.match(user):
            raise SecureSetupError(f"user name {user!r} must match {_USER.pattern}")
        passwords.setdefault(user, secrets.token_urlsafe(PASSWORD_BYTES))
    return passwords


def passwords_text(passwords: dict[str, str]) -> str:
    """The dictionary file's text: one ``user:password`` line per user."""
    return "".join(f"{user}:{password}\n" for user, password in passwords.items())
