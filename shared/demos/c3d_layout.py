"""A C3D file's structure, checked in Python before ezc3d reads it.

ezc3d trusts the sizes a file gives. Four bytes changed in a parameter
section made it crash (a parameter of 212 dimensions) or ask for 12 GB (a
description length byte of 246, which it reads as -10 and then as 4 billion
characters). This walk of the header and the parameter section refuses such
a file naming what is wrong, in well under a millisecond; what it does not
catch, reading in a child process (``c3d_reading``) does.

The format: 512-byte blocks. The header (block 1): byte 0 the parameter
section's first block, byte 1 the key 0x50; 16-bit words follow (points,
analog samples, first and last frame, ...). The parameter section: 4 bytes
(byte 3 the processor type: 84 Intel, 85 DEC, 86 MIPS), then records, each
the name's length (a signed byte; 0 ends the section), the group id (a
signed byte, negative for a group, a parameter's group otherwise), the name,
and a 16-bit offset from that offset to the next record (0: this is the
last). A group then has a description (a length byte, the text); a parameter
its type (-1 char, 1 byte, 2 16-bit integer, 4 float), number of dimensions
(at most 7), the dimensions (a byte each), the values and a description.
ezc3d, as the format's readers, takes the sizes of the data from the
parameters (POINT:USED points, ANALOG:USED channels at ANALOG:RATE).
"""

from __future__ import annotations

import math
import mmap
import struct
from pathlib import Path
from typing import NamedTuple, NoReturn

from shared.errors import DemoFileError

#: A C3D file's block [bytes].
BLOCK = 512
#: The header's second byte in every C3D file.
KEY = 0x50
#: Processor types (parameter section, byte 3) ezc3d reads: Intel and DEC.
INTEL, DEC, MIPS = 84, 85, 86
#: Bytes per value of each parameter type (-1 is a character).
TYPE_SIZE = {-1: 1, 1: 1, 2: 2, 4: 4}
#: Most dimensions a C3D parameter may have.
MAX_DIMENSIONS = 7
#: Longest record name quoted in an error as it is [characters].
MAX_NAME = 32
#: Bytes of a file's start looked at to tell text (a CSV) from C3D.
TEXT_START = 64
#: Bytes of text: printable ASCII, tab, line feed, carriage return.
TEXT_BYTES = frozenset(range(0x20, 0x7F)) | {0x09, 0x0A, 0x0D}


class C3DLayout(NamedTuple):
    """What a C3D file's header says of its frames.

    Attributes:
        first: The header's first frame (word 4).
        last: Its last frame (word 5).
    """

    first: int
    last: int


class _Parameter(NamedTuple):
    """A parameter's type (a ``TYPE_SIZE`` key) and its values as stored."""

    kind: int
    values: bytes


def check_c3d_layout(path: Path) -> C3DLayout:
    """The header's frames of a C3D file whose structure ezc3d can read.

    Raises:
        DemoFileError: naming what is wrong: a header, parameter section or
            parameter size that is not C3D's, or data that would not fit in
            the file.
    """
    try:
        with path.open("rb") as file:
            size = path.stat().st_size
            _refuse_text(path, file.read(TEXT_START))
            if size < BLOCK:
                _refuse(path, f"{size} bytes, less than a C3D header")
            with mmap.mmap(file.fileno(), 0, access=mmap.ACCESS_READ) as data:
                return _layout(path, data)
    except (OSError, ValueError) as exc:
        raise DemoFileError(str(path), f"cannot be read ({exc})") from None


def _layout(path: Path, data: mmap.mmap) -> C3DLayout:
    """Check the header, the parameters and the data's size."""
    header = bytes(data[:BLOCK])
    if header[1] != KEY:
        _refuse(path, f"its second byte is {header[1]:#04x}, a C3D file's is 0x50")
    section = (header[0] - 1) * BLOCK
    if header[0] < 2 or section + 4 > len(data):
        where = (
            "in the header" if header[0] < 2 else f"past its end ({len(data)} bytes)"
        )
        _refuse(path, f"its header puts the parameters at block {header[0]}, {where}")
    processor = data[section + 3]
    if processor not in (INTEL, DEC):
        _refuse(path, _processor_problem(processor))
    records = _records(path, data, section + 4)
    _check_data_size(path, records, header, len(data), processor)
    first, last = struct.unpack_from("<HH", header, 6)
    return C3DLayout(first, last)


def _processor_problem(processor: int) -> str:
    if processor == MIPS:
        return (
            "it is written for a MIPS processor (big-endian, parameter section "
            "byte 3 is 86), which the C3D reader (ezc3d) cannot read; export it "
            "for Intel"
        )
    return (
        f"its processor type (parameter section byte 3) is {processor}, "
        "not a C3D one (84 Intel, 85 DEC, 86 MIPS)"
    )


def _records(path: Path, data: mmap.mmap, at: int) -> dict[str, _Parameter]:
    """The parameter section's parameters, by ``GROUP:NAME``.

    Each record must end where the previous one's link puts the next, as
    ezc3d requires.
    """
    parameters: dict[str, _Parameter] = {}
    groups: dict[int, str] = {}
    while True:
        length, group = struct.unpack("bb", _take(path, data, at, 2, "a record"))
        if length == 0:
            return parameters
        name, parameter, following = _record(path, data, at, abs(length), groups)
        if group < 0:
            groups[-group] = name
        else:
            parameters[f"{groups.get(group, group)}:{name}"] = parameter
        if following == 0:
            return parameters
        at = following


def _record(
    path: Path, data: mmap.mmap, at: int, length: int, groups: dict[int, str]
) -> tuple[str, _Parameter, int]:
    """One record at byte ``at`` whose name is ``length`` bytes long.

    Returns:
        Its name; its parameter (of kind 0 for a group); the byte where the
        next record begins (0 if none).
    """
    group = struct.unpack_from("b", data, at + 1)[0]
    if group == 0:
        _corrupt(path, f"the record at byte {at} belongs to group 0")
    raw = _take(path, data, at + 2, length, f"the name of the record at byte {at}")
    name = raw.decode("latin-1")
    label = _label(name, group, groups, at)
    link = at + 2 + length
    (offset,) = struct.unpack("<H", _take(path, data, link, 2, label))
    parameter, end = _Parameter(0, b""), link + 2
    if group > 0:
        parameter, end = _values(path, data, end, label)
    end = _after_description(path, data, end, label)
    following = link + offset if offset else 0
    if offset and following != end:
        _corrupt(
            path,
            f"{label} ends at byte {end}, but its link puts the next record at "
            f"byte {following}",
        )
    return name, parameter, following


def _values(path: Path, data: mmap.mmap, at: int, label: str) -> tuple[_Parameter, int]:
    """A parameter's type and values, and the byte after them."""
    kind, count = struct.unpack("bB", _take(path, data, at, 2, label))
    if kind not in TYPE_SIZE:
        _corrupt(path, f"{label} has type {kind}; C3D's are -1, 1, 2 and 4")
    if count > MAX_DIMENSIONS:
        _corrupt(path, f"{label} has {count} dimensions; C3D allows {MAX_DIMENSIONS}")
    if count == 0 and kind == -1:
        _corrupt(path, f"{label} is a character parameter without dimensions")
    dimensions = _take(path, data, at + 2, count, label)
    size = math.prod(dimensions) * TYPE_SIZE[kind]
    values = _take(path, data, at + 2 + count, size, f"the values of {label}")
    return _Parameter(kind, values), at + 2 + count + size


def _after_description(path: Path, data: mmap.mmap, at: int, label: str) -> int:
    """The byte after a record's description (a signed length, then text)."""
    (length,) = struct.unpack("b", _take(path, data, at, 1, label))
    if length < 0:
        _corrupt(
            path,
            f"{label} has a description of {length} characters (length byte "
            f"{length & 0xFF})",
        )
    _take(path, data, at + 1, length, f"the description of {label}")
    return at + 1 + length


def _label(name: str, group: int, groups: dict[int, str], at: int) -> str:
    """A record in an error: ``POINT:USED (at byte 526)``.

    Just its byte if the name is not text (its length is corrupt).
    """
    if not _plain(name):
        return f"the record at byte {at}"
    if group < 0:
        return f"group {name} (at byte {at})"
    owner = groups.get(group, "")
    return f"{owner if _plain(owner) else f'group {group}'}:{name} (at byte {at})"


def _plain(name: str) -> bool:
    return 0 < len(name) <= MAX_NAME and name.isascii() and name.isprintable()


def _check_data_size(
    path: Path,
    records: dict[str, _Parameter],
    header: bytes,
    size: int,
    processor: int,
) -> None:
    """Raise if the data would start outside the file, or a frame not fit in it.

    Args:
        path: The file.
        records: Its parameters.
        header: Its header, 512 bytes.
        size: Its size [bytes].
        processor: Its processor type.
    """
    blocks = -(-size // BLOCK)
    said = struct.unpack_from("<H", header, 16)[0]  # 0 in some files
    if said > blocks:
        _refuse(path, f"its header puts the data at block {said}, past its end")
    start = _number(records, "POINT:DATA_START", processor)
    block = int(said if start is None else start)
    if not header[0] < block <= blocks:
        _refuse(
            path,
            f"POINT:DATA_START puts the data at block {block}, not between its "
            f"parameters (block {header[0]}) and its end (block {blocks})",
        )
    frames = _number(records, "POINT:FRAMES", processor)
    frame = _frame_size(path, records, header, processor)
    room = size - (block - 1) * BLOCK
    if frames != 0 and frame > room:
        _refuse(
            path,
            f"its parameters make a frame {frame:g} bytes long, more than the "
            f"{room} bytes of its data: corrupt parameters",
        )


def _frame_size(
    path: Path, records: dict[str, _Parameter], header: bytes, processor: int
) -> float:
    """A frame's size [bytes].

    4 values for each point (POINT:USED) and the analog samples of its
    period, 4-byte floats if POINT:SCALE is negative, 2-byte integers
    otherwise.
    """
    points = _number(records, "POINT:USED", processor) or 0
    if points < 0:
        _corrupt(path, f"POINT:USED is {points:g} points")
    scale = _number(records, "POINT:SCALE", processor)
    if scale is None:
        scale = _float(header[12:16], processor)
    values = 4 * points + _analog_samples(path, records, processor)
    return values * (4 if scale < 0 else 2)


def _analog_samples(
    path: Path, records: dict[str, _Parameter], processor: int
) -> float:
    """Analog samples in a frame (``inf`` if not a number).

    ANALOG:USED channels of ANALOG:RATE / POINT:RATE samples each.
    """
    channels = _number(records, "ANALOG:USED", processor) or 0
    if channels < 0:
        _corrupt(path, f"ANALOG:USED is {channels:g} channels")
    if channels == 0:
        return 0
    rate = _number(records, "ANALOG:RATE", processor) or 0
    point_rate = _number(records, "POINT:RATE", processor) or 0
    if not point_rate > 0:
        return 0
    per_frame = rate / point_rate
    return channels * int(per_frame) if math.isfinite(per_frame) else math.inf


def _number(records: dict[str, _Parameter], name: str, processor: int) -> float | None:
    """The first value of a numeric parameter, ``None`` if it has none."""
    record = records.get(name)
    if record is None or record.kind == -1 or len(record.values) < record.kind:
        return None
    if record.kind == 4:
        return _float(record.values[:4], processor)
    return float(int.from_bytes(record.values[: record.kind], "little", signed=True))


def _float(raw: bytes, processor: int) -> float:
    """A 4-byte float: IEEE for Intel, VAX F (words swapped, 4 x) for DEC."""
    if processor == DEC:
        return float(struct.unpack("<f", raw[2:4] + raw[0:2])[0]) / 4
    return float(struct.unpack("<f", raw)[0])


def _take(path: Path, data: mmap.mmap, at: int, count: int, what: str) -> bytes:
    """``count`` bytes at ``at``; raise if the file ends before."""
    if at + count > len(data):
        _corrupt(path, f"{what} runs past the file's end (byte {len(data)})")
    return bytes(data[at : at + count])


def _corrupt(path: Path, problem: str) -> NoReturn:
    """Raise: the parameter section is corrupt."""
    _refuse(path, f"its parameter section is corrupt: {problem}")


def _refuse_text(path: Path, start: bytes) -> None:
    """Refuse a file whose ``start`` is text: a CSV export named ``.c3d``.

    Its second byte (``KEY``) was all the error said of it, which left a
    lab's engineer to guess what was wrong with the file.
    """
    start = start.removeprefix(b"\xef\xbb\xbf")  # Excel's BOM
    if not start.strip() or not set(start) <= TEXT_BYTES:
        return
    line = start.decode().strip().splitlines()[0]
    _refuse(
        path,
        f"it is text, not C3D (it starts {line!r}): a CSV file named .c3d? "
        "Name a CSV file .csv to import it as CSV",
    )


def _refuse(path: Path, problem: str) -> NoReturn:
    raise DemoFileError(str(path), f"not a readable C3D file: {problem}")
