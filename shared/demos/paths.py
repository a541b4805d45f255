"""Demonstration files given twice, refused up front.

Two names of one file (``a.mcap`` and ``./a.mcap``, or a link to it) would
count its trials twice: refused before any work, comparing resolved paths
(and, for files that exist, their identity). Outputs are checked by
``shared.output_paths``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from shared.errors import DemoFileError
from shared.output_paths import same_file


def check_distinct(names: Sequence[str | Path]) -> None:
    """Refuse a file given twice among ``names``.

    Raises:
        DemoFileError: naming the file (and its other name, if different).
    """
    seen: list[str | Path] = []
    for name in names:
        twin = next((s for s in seen if same_file(s, name)), None)
        if twin is not None:
            also = "" if str(twin) == str(name) else f" (also as {twin})"
            raise DemoFileError(
                str(name),
                f"given twice{also}: its trials would be counted twice",
                duplicate=str(twin),
            )
        seen.append(name)
