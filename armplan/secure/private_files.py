"""Files readable by their owner only, from the moment they exist.

Keys, passwords and client files must never be readable by others, not
even for the moment between creating a file and changing its mode: each is
created with mode 0600 (``O_EXCL``: a new file, never an old one reused
with its old mode), then written, by Python or by ``openssl``.
"""

from __future__ import annotations

import os
from pathlib import Path


def create_private(path: Path) -> Path:
    """A new, empty file at ``path``, mode 0600; returns ``path``.

    A file already there (an earlier run's scratch file left by a kill) is
    removed first, so the file is always created afresh with the mode.
    """
    os.close(_open_new(path))
    return path


def write_private(path: Path, text: str) -> Path:
    """Write ``text`` into a new owner-only file at ``path``; returns ``path``."""
    with os.fdopen(_open_new(path), "w") as file:
        file.write(text)
    return path


def _open_new(path: Path) -> int:
    path.unlink(missing_ok=True)
    return os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
