"""Where the fit service may read demonstration files, and nowhere else.

A fit request names demonstration files; the service resolves each name
inside one directory (``$ARMPLAN_DEMOS_DIR``, else its working directory)
and refuses a name that leads outside it (``..``, an absolute path, a
symbolic link out) or that is not an ``.mcap`` file, so a request cannot
make the service open arbitrary files.
"""

from __future__ import annotations

import os
from pathlib import Path

from shared.errors import InvalidInputError

#: Environment variable naming the fit service's demonstration directory.
DEMOS_DIR_ENV = "ARMPLAN_DEMOS_DIR"


def demos_dir() -> Path:
    """The directory demonstration files are read from (resolved)."""
    return Path(os.environ.get(DEMOS_DIR_ENV) or os.getcwd()).resolve()


def demo_file(name: str, root: Path) -> Path:
    """The file ``name`` inside ``root``.

    Raises:
        InvalidInputError: if ``name`` is not an ``.mcap`` file name, holds a
            NUL character or leads outside ``root``.
    """
    if not name.endswith(".mcap"):
        raise InvalidInputError(
            f"demonstration file {name!r} must be an .mcap file", field="files"
        )
    if "\0" in name:  # no file has one; resolving it raised ValueError
        raise InvalidInputError(
            f"demonstration file {name!r} holds a NUL character, which no file "
            "name can",
            field="files",
        )
    path = (root / name).resolve()
    if not path.is_relative_to(root):
        raise InvalidInputError(
            f"demonstration file {name!r} is outside the fit service's "
            f"demonstration directory (${DEMOS_DIR_ENV})",
            field="files",
        )
    return path
