"""What ``armplan experiment pace`` writes: JSON, a table, one PNG.

Into the output directory: ``pace.json`` (``pace_summary.summary``),
``pace.md`` (per method and kind of task: planned, refused, median, mean
and largest ratio to human pace, how many slow, how many of those near a
limit and how many of the others short) and ``pace-ratios.png`` (each
method's ratios, sorted, per kind). A run not of the defaults names its
files after what it changed (``pace-left-mu-0.03-omega-0.01.json``; the
command builds the name), so it never replaces the default run's.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import FormatStrFormatter, NullFormatter

from armplan.experiments.figure_file import COLOURS, new_figure, save_png
from armplan.experiments.markdown_table import markdown_tables
from armplan.experiments.pace_summary import KINDS, SHORT, SLOW
from armplan.experiments.similarity_report import Table, make_dir
from shared.output_paths import replaced_together

#: Where the ratio axis is labelled [-] (those within its range) ...
RATIO_TICKS = (1, 1.5, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64)
#: ... or, where fewer than two of those fall within it, these.
FINE_TICKS = (1, 1.1, 1.2, 1.3, 1.4, 1.5, 1.75, 2, 2.25, 2.5, 2.75, 3, 3.5, 4, 5)

#: The table's columns after method and kind, with the summary's keys.
_COLUMNS = {
    "tasks": "tasks",
    "planned": "planned",
    "refused": "refused",
    "median_ratio": "median T/asked",
    "mean_ratio": "mean T/asked",
    "max_ratio": "max T/asked",
    "slow": f"over {SLOW:g}",
    "slow_near_limit": "of those near a limit",
    "slow_short": f"others short (< {SHORT:g} s)",
}


def methods_of(summary: dict[str, Any]) -> list[str]:
    """The methods in the summary, in its order."""
    return [k for k in summary if k != "protocol"]


def tables(summary: dict[str, Any]) -> dict[str, Table]:
    """One table: a row per method and kind of task ("-" where none was planned)."""
    rows = [
        [method, name, *(_cell(summary[method][name][key]) for key in _COLUMNS)]
        for name in KINDS.values()
        for method in methods_of(summary)
    ]
    return {"pace": (["method", "tasks of", *_COLUMNS.values()], rows)}


def _cell(value: Any) -> Any:
    return "-" if value is None else value


def write_report(
    summary: dict[str, Any], out: str | Path, name: str = "pace"
) -> list[Path]:
    """Write the JSON, the table and the figure; returns the paths.

    ``name.json``, ``name.md`` and ``name-ratios.png``. All three replace
    older files of their names together, or none does
    (``shared.output_paths.replaced_together``).

    Raises:
        InvalidInputError: if the directory cannot be made or written.
    """
    out = make_dir(out)
    paths = [out / f"{name}{end}" for end in (".json", ".md", "-ratios.png")]
    with replaced_together(paths) as files:
        data, table, figure = files
        files.write_text(data, json.dumps(summary, indent=2) + "\n")
        files.write_text(table, markdown_tables(tables(summary)))
        plot_ratios(summary, figure)
    return paths


def ratio_ticks(low: float, high: float) -> list[float]:
    """Ratios [-] to label on an axis from ``low`` to ``high``: at least two.

    :data:`RATIO_TICKS` within the range, else :data:`FINE_TICKS`, else the
    range's ends (3 significant digits).
    """
    for ticks in (RATIO_TICKS, FINE_TICKS):
        inside = [float(t) for t in ticks if low <= t <= high]
        if len(inside) >= 2:
            return inside
    return [float(f"{low:.3g}"), float(f"{high:.3g}")]


def plot_ratios(summary: dict[str, Any], path: Path) -> Path:
    """Write :func:`ratio_figure` of ``summary`` to ``path`` as PNG."""
    return save_png(ratio_figure(summary), path)


def ratio_figure(summary: dict[str, Any]) -> Figure:
    """Each method's ratios to human pace, sorted, one panel per kind of task.

    The ratio axis is logarithmic and labelled at :data:`RATIO_TICKS` (a
    log axis labels only decades, and no decade but 1 falls in 1..6). A
    method with one planned task is drawn as a dot (a step of one point
    draws nothing).
    """
    figure = new_figure(10.0, 4.0)
    for k, name in enumerate(KINDS.values()):
        ax = figure.add_subplot(1, len(KINDS), k + 1)
        for method in methods_of(summary):
            ratios = np.sort(summary[method][name]["ratios"])
            share = np.arange(1, len(ratios) + 1) / max(len(ratios), 1)
            ax.step(ratios, share, where="post", color=COLOURS.get(method),
                    marker="o" if len(ratios) == 1 else None,
                    label=f"{method} ({len(ratios)} planned)")  # fmt: skip
        ax.axvline(SLOW, color="grey", ls=":", lw=0.8)
        ax.set_xscale("log")
        low, high = ax.get_xlim()
        ax.set_xticks(ratio_ticks(low, high))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlim(low, high)
        ax.set_xlabel("trajectory duration / human duration [-]")
        ax.set_ylabel("share of the planned tasks [-]")
        ax.set_title(f"random {name}")
        ax.legend(loc="lower right", fontsize=8)
        ax.grid(alpha=0.3)
    return figure
