"""A CSV trial's samples named by the lines of the file they were read from.

A lab member mends a refused trial in the file: an error that names the
trial but not its lines left a file of thousands of rows to search. A CSV
trial's samples are its rows, in order, and the frames of rows left out
(``missing_rows``), which have no line: each sample's line (from 1) is
an ``int`` or ``None``. A C3D trial has no lines (``None``): its messages
name frames and times only, and these functions give ``""`` and ``{}``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

#: Each sample's line in the file (``None`` for a frame of a missing row),
#: or ``None`` for a trial not read from a CSV file.
Lines = Sequence[int | None] | None


def trial_span(lines: Lines) -> str:
    """The trial's lines for a message, ``" (lines 2-31)"``; ``""`` without."""
    if not lines:
        return ""
    return f" ({lines_of(lines, 0, len(lines) - 1)})"


def sample_line(lines: Lines, k: int) -> str:
    """Sample ``k``'s line for a message, ``", line 7"``; ``""`` without.

    A frame of a missing row names the rows around it:
    ``", no row: between lines 7 and 8"``.
    """
    if not lines:
        return ""
    if lines[k] is not None:
        return f", line {lines[k]}"
    before, after = _around(lines, k)
    return f", no row: between lines {before} and {after}"


def lines_of(lines: Sequence[int | None], first: int, last: int) -> str:
    """Samples ``first``..``last`` as lines: ``"lines 31-90"`` or ``"line 31"``.

    Frames of missing rows at either end count as the rows beside them.
    """
    low, high = line_range(lines, first, last)
    return f"line {low}" if low == high else f"lines {low}-{high}"


def line_range(lines: Sequence[int | None], first: int, last: int) -> tuple[int, int]:
    """The first and last line [from 1] of samples ``first``..``last``.

    The rows among them, or if there are none (a run of missing rows) the
    rows around them.
    """
    rows = [n for n in lines[first : last + 1] if n is not None]
    if rows:
        return rows[0], rows[-1]
    return _around(lines, first)[0], _around(lines, last)[1]


def line_evidence(lines: Lines, first: int, last: int | None = None) -> dict[str, Any]:
    """Evidence of samples ``first``..``last`` (one sample without ``last``).

    ``{"line": 7}`` for one sample read from a row, else ``{"first_line",
    "last_line"}`` (``line_range``); ``{}`` for a trial without lines.
    """
    if not lines:
        return {}
    last = first if last is None else last
    if first == last and lines[first] is not None:
        return {"line": lines[first]}
    low, high = line_range(lines, first, last)
    return {"first_line": low, "last_line": high}


def _around(lines: Sequence[int | None], k: int) -> tuple[int, int]:
    """The lines of the rows before and after sample ``k``, a missing row's.

    A trial's first and last samples are rows, so both exist.
    """
    before = next(n for n in reversed(lines[:k]) if n is not None)
    after = next(n for n in lines[k:] if n is not None)
    return before, after
