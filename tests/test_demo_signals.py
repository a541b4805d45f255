"""``armplan demo`` told to stop by SIGTERM, and a reader that leaves early.

SIGTERM (``timeout``, systemd, ``docker stop``) shuts everything down as
Ctrl-C does, but is reported as what it is: "terminated", exit 143 (the
shell's code for SIGTERM), not "interrupted", 130.
"""

from __future__ import annotations

import signal
from pathlib import Path

from tests.test_demo import RUN_TIMEOUT, STOP_TIMEOUT, Demo, descendants


def test_sigterm_during_start_up_is_terminated_143(tmp_path: Path) -> None:
    """SIGTERM while the processes start: exit 143, "terminated" on stderr,
    no process left."""
    demo = Demo("--out", str(tmp_path / "results"))
    try:
        demo.wait_for_line("starting the router", RUN_TIMEOUT)
        demo.seen |= descendants(demo.process.pid)
        demo.process.send_signal(signal.SIGTERM)
        code, _, stderr = demo.finish(STOP_TIMEOUT)
        assert code == 143, stderr[-2000:]
        assert stderr.endswith("armplan: terminated\n")
        assert demo.leftovers() == []
    finally:
        demo.kill_leftovers()
