"""What ``armplan experiment similarity`` writes: tables, JSON, two PNGs.

Into the output directory, for path source ``human`` (or ``planned``;
``similarity-human-palm`` etc. with ``--palm``):
``similarity-human.json`` (``similarity_summary.summary``),
``similarity-human.md`` (the tables below, in centimetres),
``similarity-human-distribution.png`` (Fig. 14) and
``similarity-human-point-means.png`` (Fig. 15). Reaches left out with
``--palm`` get a table of their own, its title counting them.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from armplan.experiments.markdown_table import markdown_tables
from armplan.experiments.similarity import ReachError
from armplan.experiments.similarity_plots import plot_distribution, plot_point_means
from armplan.experiments.similarity_summary import POSTURE
from shared.output_paths import make_output_folder, replaced_together

CM = 100.0
Table = tuple[list[str], list[list[Any]]]


def tables(summary: dict[str, Any]) -> dict[str, Table]:
    """The tables of a summary: overall, per point, by primitive count [cm]."""
    methods = [m for m in ("mp", "least-norm", "single") if m in summary]
    overall = [
        [m, *(CM * summary[m][k] for k in _OVERALL_KEYS), summary[m]["reaches"]]
        for m in methods
    ]
    header = ["method", "mean [cm]", "sd [cm]", "max [cm]", "wrist [cm]", "reaches"]
    if POSTURE in summary[methods[0]]:
        header[1:1] = ["mean S", "sd S"]
        for row in overall:
            numbers = summary[row[0]]
            row[1:1] = [numbers[POSTURE], numbers["sd_posture_similarity"]]
    points = list(summary[methods[0]]["per_point_mean_elbow_error_m"])
    per_point = [
        [p, *(CM * summary[m]["per_point_mean_elbow_error_m"][p] for m in methods)]
        for p in points
    ]
    return {
        "overall": (header, overall),
        **_left_out(summary),
        "per point": (["point", *(f"{m} [cm]" for m in methods)], per_point),
        "by mp primitives": _by_count(summary, "by_mp_primitive_count", methods),
        "by human primitives": _by_count(summary, "by_human_primitive_count", methods),
    }


def _left_out(summary: dict[str, Any]) -> dict[str, Table]:
    """The reaches left out with ``--palm`` (none: no table), counted in the title.

    The overall table's ``reaches`` count only those compared; this says
    how many more there were and why each is not.
    """
    skipped = summary["protocol"].get("skipped") or []
    if not skipped:
        return {}
    count = len(skipped)
    title = (
        f"left out: {count} reach{'es' if count != 1 else ''} "
        "(no posture within the limits meets the subject's palm)"
    )
    rows = [[s.get("name") or s["subject"], s["reason"]] for s in skipped]
    return {title: (["reach", "why"], rows)}


_OVERALL_KEYS = (
    "mean_elbow_error_m",
    "sd_elbow_error_m",
    "max_elbow_error_m",
    "mean_wrist_error_m",
)


def _by_count(summary: dict[str, Any], key: str, methods: Sequence[str]) -> Table:
    rows = [
        [count, group["reaches"], *(CM * group[m] for m in methods)]
        for count, group in summary[key].items()
    ]
    return (["primitives", "reaches", *(f"{m} [cm]" for m in methods)], rows)


def write_report(
    rows: Sequence[ReachError], summary: dict[str, Any], out: str | Path, name: str
) -> list[Path]:
    """Write the JSON, the tables and the two figures; returns the paths.

    All four replace older files of their names together, or none does
    (``shared.output_paths.replaced_together``).

    Raises:
        InvalidInputError: if the directory cannot be made or written.
    """
    out = make_dir(out)
    ends = (".json", ".md", "-distribution.png", "-point-means.png")
    paths = [out / f"{name}{end}" for end in ends]
    palm = ", palm turned" if summary["protocol"].get("palm") else ""
    title = f"elbow error on NAO, {summary['protocol']['path']} wrist path{palm}"
    with replaced_together(paths) as files:
        data, table, spread, means = files
        files.write_text(data, json.dumps(summary, indent=2) + "\n")
        files.write_text(table, markdown_tables(tables(summary)))
        plot_distribution(rows, spread, title)
        plot_point_means(rows, means, title)
    return paths


def make_dir(path: str | Path) -> Path:
    """``path`` as a directory, made if missing; a typed error if impossible."""
    return make_output_folder(path)
