"""Which hardware a benchmark ran on.

The bars of the issues are absolute times "on this machine's hardware", and
the machines this project runs on are not all alike: the same commit planned
the one-second reach in about 10 ms on one processor and 3 ms on another.
Naming the processor beside every run keeps figures from different hardware
from being read as one machine's good and bad moments.
"""

from __future__ import annotations

import platform
from pathlib import Path

#: Where Linux describes the processor.
CPUINFO = Path("/proc/cpuinfo")


def cpu_model(cpuinfo: Path = CPUINFO) -> str:
    """The processor's model name, e.g. ``"Intel(R) Xeon(R) Processor"``.

    Linux's ``model name`` line of ``cpuinfo``; elsewhere (or when that
    file has no such line) what :func:`platform.processor` says, and
    ``"unknown"`` when that is empty too.
    """
    try:
        lines = cpuinfo.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        lines = []
    for line in lines:
        key, _, value = line.partition(":")
        if key.strip() == "model name" and value.strip():
            return " ".join(value.split())
    return platform.processor().strip() or "unknown"
