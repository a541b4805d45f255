"""The ``armplan record`` command line the recorder's tests run."""

from __future__ import annotations

import os
import subprocess
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


def start_recording(command: list[str]) -> subprocess.Popen[str]:
    """Start ``command`` (an ``armplan record``); return once it says it records.

    Its stdout and stderr are pipes; no ``ARMPLAN_ZENOH_CONFIG`` of the
    environment applies. The caller kills it in the end.
    """
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "ARMPLAN_ZENOH_CONFIG": ""},
    )
    assert process.stdout is not None
    first = process.stdout.readline()
    if "armplan record: recording" not in first:
        process.kill()
        _, stderr = process.communicate(timeout=30)
        raise AssertionError(f"not recording: {first!r} {stderr!r}")
    return process
