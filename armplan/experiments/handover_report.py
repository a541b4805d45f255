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
from armplan.experiments.markdown_table import markdown_tables
from armplan.experiments.similarity_report import Table, make_dir
from shared.output_paths import replaced_together


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

    All three replace older files of their names together, or none does
    (``shared.output_paths.replaced_together``).

    Raises:
        InvalidInputError: if the directory cannot be made or written.
    """
    out = make_dir(out)
    paths = [out / f"{name}{end}" for end in (".json", ".md", "-similarity.png")]
    starts = summary["protocol"]["starts"]
    title = f"posture similarity to the human reference, handover task ({starts})"
    with replaced_together(paths) as files:
        data, table, figure = files
        files.write_text(data, json.dumps(summary, indent=2) + "\n")
        files.write_text(table, markdown_tables(tables(reference, series, summary)))
        plot_similarity(reference, series, figure, title)
    return paths
