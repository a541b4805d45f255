"""The report a test gives on a process tree that outlived its wait."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

from hang_report import hang_report

#: A parent that starts a child stuck in ``stuck_here``, then waits for it.
PARENT = """
import subprocess, sys
child = subprocess.Popen([sys.executable, "-c", sys.argv[1]])
print(child.pid, flush=True)
child.wait()
"""
CHILD = """
import time
def stuck_here():
    while True:
        time.sleep(0.05)
stuck_here()
"""


def test_a_report_names_every_process_its_stack_and_the_logs(tmp_path: Path) -> None:
    """Both processes with their command lines, the child's Python frames
    (``stuck_here``), or py-spy's own reason where it may not read them, the
    log's tail and the stderr given."""
    log = tmp_path / "child.log"
    log.write_text("early line\n" + "x" * 5000 + "\nlast words of the child\n")
    parent = subprocess.Popen(
        [sys.executable, "-c", PARENT, CHILD], stdout=subprocess.PIPE, text=True
    )
    try:
        assert parent.stdout is not None
        child = int(parent.stdout.readline())
        time.sleep(0.5)  # the child inside stuck_here
        report = hang_report(parent.pid, [log], stderr="said on stderr")
    finally:
        parent.kill()
        parent.wait(10)
        subprocess.run(["kill", "-9", str(child)], check=False)
    assert f"--- process {parent.pid}: " in report
    assert f"--- process {child}: " in report
    child_part = report.split(f"--- process {child}: ", 1)[1]
    assert "stuck_here" in child_part or "ermission" in child_part, child_part
    assert "last words of the child" in report
    assert "early line" not in report  # a tail, not the whole file
    assert "said on stderr" in report


def test_a_process_gone_is_left_out(tmp_path: Path) -> None:
    """A PID that no longer runs gives no process part; no stderr given, no
    stderr part; a log that cannot be read says so."""
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait(10)
    report = hang_report(gone.pid, [tmp_path / "missing.log"])
    assert "--- process" not in report
    assert "--- stderr" not in report
    assert "unreadable" in report
