"""The processor a benchmark names (armplan.bench.machine)."""

from __future__ import annotations

import platform
from pathlib import Path

from armplan.bench.machine import cpu_model

CPUINFO = """processor\t: 0
vendor_id\t: GenuineIntel
model name\t: Intel(R)  Xeon(R) Processor   @ 2.60GHz
flags\t\t: fpu vme

processor\t: 1
model name\t: Intel(R)  Xeon(R) Processor   @ 2.60GHz
"""


def test_the_model_name_line_is_read_with_its_spaces_folded(tmp_path: Path) -> None:
    """Linux's 'model name' is the processor, once, single-spaced."""
    info = tmp_path / "cpuinfo"
    info.write_text(CPUINFO, encoding="utf-8")
    assert cpu_model(info) == "Intel(R) Xeon(R) Processor @ 2.60GHz"


def test_without_cpuinfo_the_platform_says(tmp_path: Path) -> None:
    """No cpuinfo file (or no model line): the platform's word, else 'unknown'."""
    expected = platform.processor().strip() or "unknown"
    assert cpu_model(tmp_path / "absent") == expected
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nmodel name\t:   \n", encoding="utf-8")
    assert cpu_model(info) == expected


def test_this_machine_has_a_name() -> None:
    """The real file (or the fallback) gives a non-empty one-line name."""
    name = cpu_model()
    assert name and "\n" not in name and name == name.strip()
