"""Reading an input file whole, up to a size: devices and pipes included.

A size check by ``stat().st_size`` passes any file that is not a regular
one (``/dev/zero``, a named pipe, ``<(...)``: st_size 0), and reading it
whole then takes memory without end. :func:`read_at_most` reads one byte
past the limit instead, so it refuses such a file as soon as it has read
too much, whatever kind it is.

:func:`without_byte_order_mark` drops the UTF-8 byte-order mark an editor
may put first (Windows Notepad, Excel's "CSV UTF-8"): JSON parsers refuse it
at "line 1 column 1", a place where the file shows nothing wrong.
"""

from __future__ import annotations

import errno
from pathlib import Path

#: Largest JSON input file read [bytes]: the services' default payload limit.
MAX_INPUT_BYTES = 16 * 1024 * 1024
#: The UTF-8 byte-order mark, U+FEFF encoded.
UTF8_BOM = b"\xef\xbb\xbf"


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


def without_byte_order_mark(data: bytes) -> bytes:
    """``data`` without the UTF-8 byte-order mark it may start with.

    The CSV readers already open their files as ``utf-8-sig``; a JSON task
    file saved by the same editors gets the same reading.
    """
    return data.removeprefix(UTF8_BOM)
