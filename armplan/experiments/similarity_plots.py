"""The similarity experiment's figures, like the paper's Fig. 14 and Fig. 15.

- ``plot_distribution``: per grid point, the distribution of the subjects'
  elbow errors (a box per method, side by side; whiskers at the extremes,
  every subject's error a dot), like Fig. 14.
- ``plot_point_means``: per grid point, the mean over the subjects (a bar
  per method), with the 1 cm bar of the SPEC, like Fig. 15.

Errors are drawn in centimetres, as in the paper.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes

from armplan.experiments.figure_file import COLOURS, new_figure, save_png
from armplan.experiments.similarity import ReachError
from armplan.experiments.similarity_summary import ELBOW_BAR, errors_by_point
from armplan.experiments.subject_reach import point_label
from shared.messages import Method

CM = 100.0


def _methods(rows: Sequence[ReachError]) -> list[Method]:
    return sorted({r.method for r in rows}, key=list(Method).index)


def _offsets(count: int, width: float) -> np.ndarray:
    """Offsets of ``count`` side-by-side items about a point's position."""
    return (np.arange(count) - (count - 1) / 2.0) * width


def plot_distribution(rows: Sequence[ReachError], path: str | Path, title: str) -> Path:
    """Fig. 14: the elbow error distribution per point and method."""
    figure = new_figure(11.0, 4.5)
    ax = figure.add_subplot()
    methods = _methods(rows)
    points = sorted({r.point for r in rows})
    width = 0.8 / len(methods)
    for method, dx in zip(methods, _offsets(len(methods), width), strict=True):
        errors = errors_by_point(rows, method)
        data = [CM * np.array(errors[p]) for p in points]
        where = np.arange(len(points)) + dx
        _boxes(ax, data, where, width * 0.85, COLOURS[method.value])
        ax.plot([], [], color=COLOURS[method.value], label=method.value, lw=6)
    _point_axis(ax, points, "elbow error [cm]", title)
    return save_png(figure, path)


def _boxes(
    ax: Axes, data: list[np.ndarray], where: np.ndarray, width: float, colour: str
) -> None:
    """Boxes with whiskers at the extremes and every value as a dot."""
    parts = ax.boxplot(
        data, positions=where, widths=width, whis=(0, 100), patch_artist=True,
        showfliers=False, manage_ticks=False,
    )  # fmt: skip
    for box in parts["boxes"]:
        box.set(facecolor=colour, alpha=0.35, edgecolor=colour)
    for x, values in zip(where, data, strict=True):
        ax.plot(np.full(len(values), x), values, ".", color=colour, ms=3)


def plot_point_means(rows: Sequence[ReachError], path: str | Path, title: str) -> Path:
    """Fig. 15: the mean elbow error per point and method, with the 1 cm bar."""
    figure = new_figure(11.0, 4.0)
    ax = figure.add_subplot()
    methods = _methods(rows)
    points = sorted({r.point for r in rows})
    width = 0.8 / len(methods)
    for method, dx in zip(methods, _offsets(len(methods), width), strict=True):
        errors = errors_by_point(rows, method)
        means = [CM * float(np.mean(errors[p])) for p in points]
        ax.bar(np.arange(len(points)) + dx, means, width, color=COLOURS[method.value],
               label=method.value)  # fmt: skip
    ax.axhline(CM * ELBOW_BAR, color="k", ls="--", lw=1, label="1 cm (SPEC bar)")
    _point_axis(ax, points, "mean elbow error [cm]", title)
    return save_png(figure, path)


def _point_axis(ax: Axes, points: list[int], label: str, title: str) -> None:
    ax.set_xticks(np.arange(len(points)), [point_label(p) for p in points])
    ax.set_xlabel("grid point")
    ax.set_ylabel(label)
    ax.set_ylim(bottom=0.0)
    ax.set_title(title)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(axis="y", alpha=0.3)
