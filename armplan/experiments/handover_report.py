"""What ``armplan experiment handover`` writes: table, JSON, one PNG.

Into the output directory, ``name`` being e.g. ``handover-chained``:
``<name>.json`` (``handover_summary.summary``), ``<name>.md`` (mean S per
method, and per movement) and ``<name>-similarity.png`` (Fig. 18).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from armplan.experiments.handover import SimilaritySeries
from armplan.experiments.handover_plots import plot_similarity
from armplan.experiments.handover_summary import movement_table
from armplan.experiments.human_reference import ReferenceMovement
from armplan.experiments.markdown_table import markdown_table
from armplan.experiments.similarity_report import Table, make_dir, write_text


def tables(
    reference: Sequence[ReferenceMovement],
    series: Sequence[SimilaritySeries],
    summary: dict[str, Any],
) -> dict[str, Table]:
    """The tables: S per method overall, and per movement."""
    names = [s.method.value for s in series]
    overall = [
        [
            m,
            *(
                summary[m][k]
                for k in ("mean_similarity", "sd_similarity", "min_similarity")
            ),
        ]
        for m in names
    ]
    return {
        "overall": (["method", "mean S", "sd S", "min S"], overall),
        "per movement": (
            ["movement", "duration [s]", *(f"{m} S" for m in names)],
            movement_table(reference, series),
        ),
    }


def write_report(
    reference: Sequence[ReferenceMovement],
    series: Sequence[SimilaritySeries],
    summary: dict[str, Any],
    out: str | Path,
    name: str,
) -> list[Path]:
    """Write the JSON, the tables and the figure; returns the paths.

    Raises:
        InvalidInputError: if the directory cannot be made or written.
    """
    out = make_dir(out)
    written = [write_text(out / f"{name}.json", json.dumps(summary, indent=2) + "\n")]
    text = "".join(
        f"**{title}**\n\n" + markdown_table(*table) + "\n"
        for title, table in tables(reference, series, summary).items()
    )
    written.append(write_text(out / f"{name}.md", text))
    starts = summary["protocol"]["starts"]
    title = f"posture similarity to the human reference, handover task ({starts})"
    figure = out / f"{name}-similarity.png"
    written.append(plot_similarity(reference, series, figure, title))
    return written
