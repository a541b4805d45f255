"""Reading an input file whole, up to a size: devices and pipes included.

A size check by ``stat().st_size`` passes any file that is not a regular
one (``/dev/zero``, a named pipe, ``<(...)``: st_size 0), and reading it
whole then takes memory without end. :func:`read_at_most` reads one byte
past the limit instead, so it refuses such a file as soon as it has read
too much, whatever kind it is.
"""

from __future__ import annotations

import errno
from pathlib import Path

#: Largest JSON input file read [bytes]: the services' default payload limit.
MAX_INPUT_BYTES = 16 * 1024 * 1024


def read_at_most(path: str | Path, limit: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of the file at ``path``, if it holds at most ``limit``.

    Raises:
        OSError: the file cannot be read; or (errno ``EFBIG``, ``strerror``
            "more than <limit> bytes") it holds more than ``limit`` bytes,
            so a caller's ``except OSError`` naming ``strerror`` says so.
    """
    with open(path, "rb") as stream:
        data = stream.read(limit + 1)
    if len(data) > limit:
        raise OSError(errno.EFBIG, f"more than {limit} bytes", str(path))
    return data
