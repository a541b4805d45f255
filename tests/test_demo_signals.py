"""``armplan demo`` told to stop by SIGTERM, and a reader that leaves early.

SIGTERM (``timeout``, systemd, ``docker stop``) shuts everything down as
Ctrl-C does, but is reported as what it is: "terminated", exit 143 (the
shell's code for SIGTERM), not "interrupted", 130. A reader that leaves
(``| head -1``) costs the demo its printed output, not its run.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

from tests.test_demo import RUN_TIMEOUT, STOP_TIMEOUT, Demo, alive, descendants


def test_sigterm_is_terminated_143(tmp_path: Path) -> None:
    """SIGTERM once every process runs: exit 143, "terminated" on stderr, no
    process left."""
    demo = Demo("--out", str(tmp_path / "results"))
    try:
        demo.wait_for_line("running:", RUN_TIMEOUT)
        demo.seen |= descendants(demo.process.pid)
        demo.process.send_signal(signal.SIGTERM)
        code, _, stderr = demo.finish(STOP_TIMEOUT)
        assert code == 143, stderr[-2000:]
        assert stderr.endswith("armplan: terminated\n")
        assert demo.leftovers() == []
    finally:
        demo.kill_leftovers()


def test_a_reader_that_leaves_early_loses_the_output_not_the_run(
    tmp_path: Path,
) -> None:
    """``armplan demo | head -1``: the pipe closes after the first line; the
    demo still plays the task, writes its files and exits 0, no process left."""
    out = tmp_path / "results"
    with (tmp_path / "stderr").open("w+") as errors:
        process = subprocess.Popen(
            [sys.executable, "-m", "armplan", "demo", "--out", str(out)],
            stdout=subprocess.PIPE,
            stderr=errors,
            text=True,
        )
        try:
            assert process.stdout is not None
            first = process.stdout.readline()
            process.stdout.close()  # as head -1 does
            started = descendants(process.pid)
            code = process.wait(RUN_TIMEOUT)
        finally:
            if process.poll() is None:
                process.kill()
                process.wait(10)
        errors.seek(0)
        stderr = errors.read()
    assert first.startswith("starting the router")
    assert code == 0, stderr[-2000:]
    assert "Traceback" not in stderr
    report = json.loads((out / "report.json").read_text())
    assert report["samples"] > 0
    assert [p for p in started if alive(p)] == []
