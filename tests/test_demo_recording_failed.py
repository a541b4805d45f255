"""``armplan demo`` whose recording fails: said as such, the rest kept.

The recorder's file is capped while the demo runs (RLIMIT_FSIZE on the
recorder's process, what a full disk does): the recorder stops at once
with exit code 1. The demo used to take the recorder's stop as a success
whatever its exit code. Now it plays the task and writes its other files,
whose summary marks the recording as failed, and exits 1 with the
recorder's reason; no process is left.
"""

from __future__ import annotations

import json
import re
import resource
from pathlib import Path

from shared.recording.reader import Recording
from tests.test_demo import RUN_TIMEOUT, Demo, descendants

#: Bytes the recording may grow by after the cap is set [bytes]: the
#: request, not the trajectory with its Foxglove poses.
ROOM = 32 * 1024


def test_a_failed_recording_is_reported_and_the_rest_written(tmp_path: Path) -> None:
    """Exit 1 naming the recorder's reason and its log; the other outputs
    written whole; the summary says the recording failed; no process left."""
    out = tmp_path / "results"
    recording = out / "session.mcap"
    demo = Demo("--out", str(out))
    try:
        running = demo.wait_for_line("running:", RUN_TIMEOUT)[-1]
        found = re.search(r"recorder \(pid (\d+)\)", running)
        assert found, running
        cap = recording.stat().st_size + ROOM
        resource.prlimit(int(found.group(1)), resource.RLIMIT_FSIZE, (cap, cap))
        demo.seen |= descendants(demo.process.pid)
        code, lines, stderr = demo.finish(RUN_TIMEOUT)
        print("\n" + "\n".join(lines) + "\n" + stderr[-2000:])
        assert code == 1, stderr[-2000:]
        last = stderr.strip().splitlines()[-1]
        assert last.startswith(
            f"armplan: error: the recorder of {recording} failed (exit code 1): "
            f"cannot write {recording}: File too large; recording stopped after "
        )
        assert last.endswith(f"; see its log {out / 'logs' / 'recorder.log'}")
        assert "Traceback" not in stderr
        said = f"  recording    {recording} (FAILED: incomplete"
        assert any(line.startswith(said) for line in lines), lines
        assert not any(line.startswith("armplan demo: done") for line in lines)
        report = json.loads((out / "report.json").read_text())
        assert report["samples"] > 0
        for name in ("trajectory.json", "behavior.xar", "play.py"):
            assert (out / name).stat().st_size > 0
        damaged = Recording(recording)
        assert sum(1 for _ in damaged) >= 1 and damaged.damage is not None
        assert demo.leftovers() == []
    finally:
        demo.kill_leftovers()
