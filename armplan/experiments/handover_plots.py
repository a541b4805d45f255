"""The handover experiment's figure, like the paper's Fig. 18.

Posture similarity S (eq. 22-23) of each method to the human reference over
the person's time through the task, one curve per method; dotted lines
divide the movements, named along the top.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from armplan.experiments.figure_file import COLOURS, new_figure, save_png
from armplan.experiments.handover import SimilaritySeries
from armplan.experiments.human_reference import ReferenceMovement


def plot_similarity(
    reference: Sequence[ReferenceMovement],
    series: Sequence[SimilaritySeries],
    path: str | Path,
    title: str,
) -> Path:
    """Fig. 18: S over time for every method."""
    figure = new_figure(11.0, 4.5)
    ax = figure.add_subplot()
    for one in series:
        mean = float(one.similarity.mean())
        ax.plot(
            one.times,
            one.similarity,
            color=COLOURS[one.method.value],
            lw=1.4,
            label=f"{one.method.value} (mean {mean:.3f})",
        )
    start = 0.0
    for move in reference:
        end = start + float(move.times[-1])
        ax.axvline(end, color="grey", ls=":", lw=0.8)
        ax.text((start + end) / 2, 1.005, move.name, rotation=60, fontsize=7,
                ha="left", va="bottom", transform=ax.get_xaxis_transform())  # fmt: skip
        start = end
    ax.set_xlim(0.0, start)
    ax.set_xlabel("the person's time through the task [s]")
    ax.set_ylabel("posture similarity S [-]")
    ax.set_title(title, pad=70)
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    return save_png(figure, path)
