"""Figures drawn off-screen (matplotlib's Agg canvas) and saved as PNG."""

from __future__ import annotations

from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from shared.errors import InvalidInputError

#: Colours of the methods, the same in every figure.
COLOURS = {"mp": "tab:red", "least-norm": "tab:blue", "single": "tab:green"}


def new_figure(width: float, height: float) -> Figure:
    """A figure of ``width`` x ``height`` [inch] on an Agg canvas."""
    figure = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def save_png(figure: Figure, path: str | Path) -> Path:
    """Write ``figure`` to ``path`` as PNG; returns the path.

    The figures are written under their partial names
    (``shared.output_paths.replaced_together``), which turns an ``OSError``
    naming the partial file into the typed error naming the final one; so
    an ``OSError`` without a file name (a full disk fails ``write()``) is
    raised again naming ``path``.

    Raises:
        OSError: naming ``path``, if the file cannot be written.
        InvalidInputError: if matplotlib refuses the path (naming it).
    """
    path = Path(path)
    try:
        figure.savefig(path, dpi=100, format="png")
    except OSError as exc:
        if exc.filename is not None:
            raise
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    except ValueError as exc:
        raise InvalidInputError(
            f"cannot write the plot {path}: {exc}", field="out"
        ) from None
    return path
