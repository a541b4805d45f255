"""The ``armplan record`` command line the recorder's tests run."""

from __future__ import annotations

import sys
from pathlib import Path

from shared.bus import BusConfig


def record_command(config: BusConfig, out: Path, *extra: str) -> list[str]:
    """``armplan record -o out --keys misc/* ...extra`` on ``config``'s router."""
    return [
        sys.executable,
        "-m",
        "armplan",
        "record",
        "-o",
        str(out),
        "--keys",
        "misc/*",
        "--connect",
        config.endpoint,
        "--namespace",
        config.namespace,
        *extra,
    ]
