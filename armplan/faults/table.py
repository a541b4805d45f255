"""The suite's table: one row per scenario, and whether the suite passed."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

from rich.table import Table

from armplan.faults.tally import Tally

#: The table's columns: (heading, key of ``Tally.row()``).
COLUMNS = (
    ("scenario", "scenario"),
    ("faults injected", "faults"),
    ("requests sent", "sent"),
    ("succeeded", "succeeded"),
    ("failed with a clear error", "typed"),
    ("unclear error", "unclear"),
    ("lost", "lost"),
    ("crashes", "crashes"),
)


def passed(tallies: Sequence[Tally]) -> bool:
    """No request lost, no unclear error, no crash, no promise unmet.

    In any scenario; a promise is what its facts must show
    (:func:`~armplan.faults.tally.unmet`): a restarted process serves again,
    the calls that needed a killed one named it, the recorders' files hold
    the plans, a good request is answered after each bad one.
    """
    return all(t.healthy for t in tallies)


def totals(tallies: Sequence[Tally]) -> dict[str, Any]:
    """The sum of every numeric column."""
    rows = [t.row() for t in tallies]
    summed: dict[str, Any] = {"scenario": "total"}
    for _, key in COLUMNS[1:]:
        summed[key] = sum(row[key] for row in rows)
    return summed


def rich_table(tallies: Sequence[Tally], title: str = "") -> Table:
    """The table for a terminal: the counts, then what showed each fault."""
    table = Table(title=title or None)
    for heading, key in COLUMNS:
        table.add_column(heading, justify="left" if key == "scenario" else "right")
    table.add_column("what showed it")
    for tally in tallies:
        row = tally.row()
        cells = [_cell(key, row[key]) for _, key in COLUMNS]
        table.add_row(*cells, _evidence(row))
    table.add_section()
    summed = totals(tallies)
    table.add_row(*(_cell(key, summed[key]) for _, key in COLUMNS), "")
    return table


def _cell(key: str, value: Any) -> str:
    if key in ("lost", "crashes", "unclear") and value:
        return f"[bold red]{value}[/]"
    return str(value)


def _evidence(row: dict[str, Any]) -> str:
    note = str(row["facts"].get("note", ""))
    kinds = ", ".join(f"{k} {n}" for k, n in sorted(row["kinds"].items()))
    crashed = "; crashed: " + ", ".join(row["crashed"]) if row["crashed"] else ""
    unmet = "; ".join(row["unmet"])
    failed = f"; [bold red]UNMET: {unmet}[/]" if unmet else ""
    return note + (f" [dim]({kinds})[/]" if kinds else "") + crashed + failed


def json_report(tallies: Sequence[Tally], load: tuple[float, float]) -> dict[str, Any]:
    """The table as JSON: rows, totals, the verdict, and the machine's load.

    Args:
        tallies: Every scenario's tally.
        load: The 1-minute load average at the start and at the end.
    """
    return {
        "scenarios": [t.row() for t in tallies],
        "total": totals(tallies),
        "passed": passed(tallies),
        "cpus": os.cpu_count(),
        "load_average": {"start": round(load[0], 2), "end": round(load[1], 2)},
    }
