"""Samples named by their CSV lines, a missing row's by the rows around it."""

from __future__ import annotations

from shared.demos.sample_lines import (
    line_evidence,
    lines_of,
    sample_line,
    trial_span,
)

#: Rows at lines 5, 6 and 9; two missing rows' frames between 6 and 9.
LINES: list[int | None] = [5, 6, None, None, 9]


def test_a_row_is_its_line_and_a_missing_row_the_rows_around() -> None:
    """A frame of a missing row names the rows on each side of it."""
    assert sample_line(LINES, 1) == ", line 6"
    assert sample_line(LINES, 3) == ", no row: between lines 6 and 9"
    assert trial_span(LINES) == " (lines 5-9)"


def test_a_span_of_missing_rows_is_the_rows_around_it() -> None:
    """Frames 2..3 have no rows: the lines 6 to 9 bound them."""
    assert lines_of(LINES, 2, 3) == "lines 6-9"
    assert lines_of(LINES, 1, 2) == "line 6"
    assert line_evidence(LINES, 2, 3) == {"first_line": 6, "last_line": 9}
    assert line_evidence(LINES, 4) == {"line": 9}


def test_a_trial_without_lines_names_none() -> None:
    """A C3D trial: no lines in messages or evidence."""
    assert trial_span(None) == sample_line(None, 0) == ""
    assert line_evidence(None, 0, 3) == {}
