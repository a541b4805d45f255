"""Printing results and errors."""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from typing import Any

from shared.errors import ArmplanError


def print_json(data: Any) -> None:
    """Print ``data`` as JSON on stdout."""
    sys.stdout.write(json.dumps(data, indent=2) + "\n")


def print_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
    """Print a plain aligned table on stdout."""
    cells = [[str(h) for h in headers]] + [[_cell(v) for v in row] for row in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    for row in cells:
        first = row[0].ljust(widths[0])
        rest = (c.rjust(w) for c, w in zip(row[1:], widths[1:], strict=True))
        sys.stdout.write("  ".join((first, *rest)) + "\n")


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.5f}"
    return str(value)


def report_error(error: ArmplanError, as_json: bool) -> int:
    """Tell the user what went wrong; returns the exit code (1)."""
    sys.stderr.write(f"armplan: error: {error.message}\n")
    if as_json:
        print_json({"error": error.to_wire()})
    return 1
