"""A picture of the decision along a path, like the paper's Fig. 7.

Left: the primitive matrix e (rows: attributes P, R, PR; columns: joints S,
E, W) of the primitive that drives most of the movement, active entries
filled, as Fig. 7 draws it for one moment. Right, top: every entry of e
over time (a filled band where the entry is 1), with the winning
primitive's name over each of its runs. Right, bottom: every candidate's g
over time, divided at each point by the largest |g| there, so that the
curves stay comparable while the probabilities change by orders of
magnitude; the winner is the curve at 1. Drawn with matplotlib's Agg
canvas (no display needed).
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from services.decide.grid_table import runs
from shared.errors import InvalidInputError
from shared.messages import Decision
from shared.primitives import ATTRIBUTES, BY_NAME, NODES


def plot_decision(decision: Decision, path: str | Path, title: str = "") -> Path:
    """Draw ``decision`` to a PNG file; returns the path written.

    Raises:
        InvalidInputError: if the file cannot be written.
    """
    path = Path(path)
    figure = Figure(figsize=(11.0, 5.5), layout="constrained")
    FigureCanvasAgg(figure)
    grid = figure.add_gridspec(2, 2, width_ratios=(1.0, 3.2))
    main = Counter(decision.primitives).most_common(1)[0][0]
    _matrix(figure.add_subplot(grid[:, 0]), main)
    times = np.array(decision.times)
    _entries(figure.add_subplot(grid[0, 1]), decision, times)
    _curves(figure.add_subplot(grid[1, 1]), decision, times)
    if title:
        figure.suptitle(title)
    try:
        figure.savefig(path, dpi=110)
    except (OSError, ValueError) as exc:
        raise InvalidInputError(
            f"cannot write the plot {path}: {exc}", field="plot"
        ) from None
    return path


def _matrix(ax: Axes, name: str) -> None:
    """The primitive matrix of ``name`` as a 3 x 3 grid of squares."""
    matrix = np.array(BY_NAME[name].matrix)
    ax.imshow(matrix, cmap="Greys", vmin=0, vmax=1.4)
    ax.set_xticks(range(3), NODES)
    ax.set_yticks(range(3), ATTRIBUTES)
    ax.set_xlabel("joint vector j")
    ax.set_ylabel("attribute vector a")
    for (row, col), value in np.ndenumerate(matrix):
        ax.text(col, row, str(value), ha="center", va="center", color="tab:red")
    ax.set_title(f"e of {name}\n(drives most points)")


def _entries(ax: Axes, decision: Decision, times: np.ndarray) -> None:
    """Each entry of the winning primitive matrix over time."""
    cells = np.array(
        [np.ravel(decision.matrices[name]) for name in decision.primitives]
    ).T
    ax.imshow(
        cells,
        aspect="auto",
        cmap="Greys",
        vmin=0,
        vmax=1.4,
        interpolation="nearest",
        extent=(times[0], times[-1], 8.5, -0.5),
    )
    labels = [f"{a} {j}" for a in ATTRIBUTES for j in NODES]
    ax.set_yticks(range(9), labels)
    ax.set_ylabel("e entry (a, j)")
    at = 0
    for name, count in runs(decision.primitives):
        if count >= 3:
            middle = times[at + count // 2]
            ax.text(middle, -0.9, name, ha="center", va="bottom", fontsize=8)
        at += count
    ax.set_title("primitive matrix over time", pad=16)


def _curves(ax: Axes, decision: Decision, times: np.ndarray) -> None:
    """Every candidate's g over time, scaled per point by the largest |g|."""
    g = np.array(decision.g)
    scale = np.max(np.abs(g), axis=1, keepdims=True)
    scale[scale == 0] = 1.0
    for index, name in enumerate(decision.candidates):
        ax.plot(times, g[:, index] / scale[:, 0], label=name)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("g / max |g|")
    ax.set_ylim(-1.1, 1.1)
    ax.legend(fontsize=7, ncol=4, loc="lower left")
    ax.set_title("accumulated mutual information g of each primitive")
