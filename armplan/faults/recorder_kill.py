"""The recorder killed mid-session: planning goes on, the file stays readable.

Plans go out in thirds around a SIGKILL of the recorder and its restart
into a new file (:func:`~armplan.faults.kill_restart.kill_and_restart`).
Nothing calls the recorder, so every plan must succeed; the killed
recorder's file must still be readable up to its last flush (read with
``recover``), and the new recorder must record every plan made after it.
"""

from __future__ import annotations

import time
from pathlib import Path

from armplan.faults.kill_restart import kill_and_restart, traffic_calls
from armplan.faults.outcome import Outcome
from armplan.faults.requests import GoodRequests
from armplan.faults.system import RECORDER, FaultSystem
from armplan.faults.tally import Tally
from armplan.faults.traffic import Traffic
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.errors import RecordingError
from shared.recording import read_records

#: Time the new recorder gets to flush what it received [s] (it flushes
#: at least every 0.2 s).
FLUSH_WAIT = 1.0


def trajectories(path: Path) -> int:
    """Planned trajectories readable in ``path`` (up to any damage); 0 if none."""
    try:
        return sum(
            1
            for r in read_records(path, recover=True)
            if r.topic.endswith(TRAJECTORY_TOPIC)
        )
    except RecordingError:  # no readable header yet
        return 0


def recorder_scenario(
    system: FaultSystem, traffic: Traffic, good: GoodRequests, count: int
) -> Tally:
    """Kill the recorder during plans, restart it into a new file.

    Facts: ``all_planned`` (every plan succeeded), ``killed_file``
    (trajectories readable in the killed recorder's file), ``new_file``
    (trajectories in the new recorder's file), ``planned_after`` (plans
    that succeeded after the restart, each of which it must hold),
    ``recovered`` (every process alive again), ``down_s`` and ``missing``.
    """
    tally = Tally("kill, restart recorder", faults=1)
    calls = traffic_calls(good, RECORDER, count)
    phases = kill_and_restart(system, traffic, calls, RECORDER)
    tally.add(phases.all())
    time.sleep(FLUSH_WAIT)
    killed_file, new_file = system.recordings()[-2:]
    kept, new = trajectories(killed_file), trajectories(new_file)
    planned = all(r.outcome is Outcome.SUCCEEDED for r in tally.results)
    after = sum(r.outcome is Outcome.SUCCEEDED for r in phases.after)
    tally.facts = {
        "all_planned": planned,
        "killed_file": kept,
        "new_file": new,
        "planned_after": after,
        "recovered": not phases.missing,
        "down_s": round(phases.down_s, 2),
        "missing": phases.missing,
        "note": f"plans {'all' if planned else 'NOT all'} succeeded; killed file "
        f"readable with {kept} trajectories, the new one has {new} of the {after} "
        "planned after the restart",
    }
    tally.crashes = system.crashes()
    return tally
