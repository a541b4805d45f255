"""Tables as Markdown text, for the results page and the command's output files."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A GitHub-flavoured Markdown table; floats with 3 decimals."""
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    for row in rows:
        lines.append("| " + " | ".join(_cell(v) for v in row) + " |")
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.3f}"
    return str(value)


def markdown_tables(
    tables: Mapping[str, tuple[Sequence[str], Sequence[Sequence[Any]]]],
) -> str:
    """Titled tables one after another: a bold title line, then the table."""
    return "".join(
        f"**{title}**\n\n" + markdown_table(*table) + "\n"
        for title, table in tables.items()
    )
