"""C3D structure check: a corrupt header or parameter section is refused by
name before ezc3d reads it; no corrupt file crashes the import."""

from __future__ import annotations

import pathlib
import random
import struct

import pytest

from shared.demos.c3d_import import read_c3d
from shared.demos.markers import MarkerMap
from shared.errors import DemoFileError
from tests.test_demos_c3d import MAP, write_reach_c3d

#: The parameter section's first byte, in files that ezc3d writes.
PARAMETERS = 512
#: Where the reach's file (``write_reach_c3d``) holds POINT:USED's value.
POINT_USED = 536


@pytest.fixture(scope="module")
def reach(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    """A valid C3D file of a reach, 8 kB, written by ezc3d."""
    path = tmp_path_factory.mktemp("reach") / "reach.c3d"
    write_reach_c3d(path)
    return path.read_bytes()


def _hunted(whole: bytes) -> list[bytes]:
    """The hunt's 40 files: 4 bytes of 512..2047 set at random (seed 3)."""
    rng = random.Random(3)
    files = []
    for _ in range(40):
        changed = bytearray(whole)
        for _ in range(4):
            at = rng.randrange(512, 2048)
            changed[at] = rng.randrange(256)
        files.append(bytes(changed))
    return files


def _refusal(path: pathlib.Path, content: bytes) -> str:
    """The import's error for a file of ``content``."""
    path.write_bytes(content)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MarkerMap.model_validate(MAP))
    return caught.value.message


@pytest.mark.parametrize(
    ("number", "fault"),
    [
        (15, "POINT:USED (at byte 526) has 212 dimensions; C3D allows 7"),
        (19, "FORCE_PLATFORM:TYPE (at byte 866) has 186 dimensions; C3D allows 7"),
        (
            30,
            "POINT:USED (at byte 526) has a description of -10 characters "
            "(length byte 246)",
        ),
    ],
)
def test_the_files_that_crashed_ezc3d_are_refused_naming_the_fault(
    tmp_path: pathlib.Path, reach: bytes, number: int, fault: str
) -> None:
    """Files 15 and 19 made ezc3d segfault (exit 139, no word), file 30 made
    it take 12.6 GB and 28 s (it read the length byte 246 as -10, then as
    4 billion): refused by the check before ezc3d, naming the parameter."""
    path = tmp_path / f"f{number}.c3d"
    assert _refusal(path, _hunted(reach)[number]) == (
        f"{path}: not a readable C3D file: its parameter section is corrupt: {fault}"
    )


def test_no_corrupt_variant_crashes_the_import(
    tmp_path: pathlib.Path, reach: bytes
) -> None:
    """120 variants, 4 bytes of the header or parameter section set at
    random (seeded): each imports or is a DemoFileError naming the file."""
    rng = random.Random(20)
    path = tmp_path / "variant.c3d"
    outcomes = {"imported": 0, "refused": 0}
    for _ in range(120):
        changed = bytearray(reach)
        for _ in range(4):
            at = rng.randrange(0, 2048)
            changed[at] = rng.randrange(256)
        path.write_bytes(changed)
        try:
            read_c3d(path, MarkerMap.model_validate(MAP))
            outcomes["imported"] += 1
        except DemoFileError as error:
            assert error.path == str(path)
            outcomes["refused"] += 1
    assert min(outcomes.values()) > 10, outcomes


def _set(whole: bytes, at: int, form: str, value: float) -> bytes:
    changed = bytearray(whole)
    struct.pack_into(form, changed, at, value)
    return bytes(changed)


@pytest.mark.parametrize(
    ("change", "fault"),
    [
        ((1, "B", 0x51), "its second byte is 0x51, a C3D file's is 0x50"),
        ((0, "B", 40), "its header puts the parameters at block 40, past its end"),
        ((0, "B", 1), "its header puts the parameters at block 1, in the header"),
        (
            (PARAMETERS + 3, "B", 86),
            "it is written for a MIPS processor (big-endian, parameter section "
            "byte 3 is 86), which the C3D reader (ezc3d) cannot read; export it "
            "for Intel",
        ),
        (
            (POINT_USED, "<h", -5536),
            "its parameter section is corrupt: POINT:USED is -5536 points",
        ),
        (
            (POINT_USED, "<h", 30000),
            "its parameters make a frame 480000 bytes long, more than the 6656 "
            "bytes of its data: corrupt parameters",
        ),
        ((16, "<H", 99), "its header puts the data at block 99, past its end"),
    ],
)
def test_a_corrupt_header_or_size_is_named(
    tmp_path: pathlib.Path,
    reach: bytes,
    change: tuple[int, str, float],
    fault: str,
) -> None:
    """The key byte, the parameters' block, the processor, the points or the
    data's block: each refused saying which, where ezc3d failed with its own
    words (30000 points: 'Data::frame method is trying to access the frame 0')
    or, for -5536 points, 'vector::_M_default_append'."""
    path = tmp_path / "corrupt.c3d"
    message = _refusal(path, _set(reach, *change))
    assert message.startswith(f"{path}: not a readable C3D file: {fault}"), message


def test_a_cut_header_is_named(tmp_path: pathlib.Path, reach: bytes) -> None:
    """100 bytes of a C3D file: less than its header."""
    path = tmp_path / "cut.c3d"
    assert _refusal(path, reach[:100]) == (
        f"{path}: not a readable C3D file: 100 bytes, less than a C3D header"
    )


@pytest.mark.parametrize("start", [b"", b"\xef\xbb\xbf"])
@pytest.mark.parametrize("size", [100, 2000])
def test_a_csv_named_c3d_is_said_to_be_text(
    tmp_path: pathlib.Path, start: bytes, size: int
) -> None:
    """A CSV export named .c3d was refused for its second byte ("its second
    byte is 0x69, a C3D file's is 0x50") or its size: it is said to be text,
    quoting its first line, whatever its size or byte-order mark."""
    header = "time,trial,RSHO_x,RSHO_y,RSHO_z"
    row = "\n0.00,0," + ",".join(["1.5"] * 3)
    text = (header + row * (size // len(row) + 1)).encode()[:size]
    path = tmp_path / "capture.c3d"
    assert _refusal(path, start + text) == (
        f"{path}: not a readable C3D file: it is text, not C3D (it starts "
        f"{header!r}): a CSV file named .c3d? Name a CSV file .csv to import "
        "it as CSV"
    )
