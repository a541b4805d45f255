"""The recorder killed mid-session: planning goes on, the file stays readable.

Plans go out in thirds around a SIGKILL of the recorder and its restart
into a new file (:func:`~armplan.faults.kill_restart.kill_and_restart`).
Nothing calls the recorder, so every plan must succeed; the killed
recorder's file must still be readable up to its last flush (read with
``recover``) and hold every plan of this scenario answered at least
``FLUSH_ALLOWANCE`` before the kill, and the new recorder must record every
plan made after it. The killed file also holds the earlier scenarios'
plans: those found in it at the scenario's start are not counted.
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
#: Time from a plan's answer to its trajectory's flush allowed the killed
#: recorder [s]: the recorder flushes at least every 0.2 s
#: (``shared.recording.rotation.FLUSH_EVERY``), the rest is for a loaded
#: machine (``tests/test_recorder_kill.py`` bounds a SIGKILL's loss by the
#: same second). The kill waits this long once half the first third is
#: answered, and those answered by then must be in the killed file.
FLUSH_ALLOWANCE = 1.0


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
    (this scenario's trajectories readable in the killed recorder's file),
    ``planned_before`` (plans that succeeded at least ``flush_allowance_s``
    before the kill, each of which it must hold), ``new_file``
    (trajectories in the new recorder's file), ``planned_after`` (plans
    that succeeded after the restart, each of which it must hold),
    ``recovered`` (every process alive again), ``down_s`` and ``missing``.
    """
    tally = Tally("kill, restart recorder", faults=1)
    time.sleep(FLUSH_WAIT)  # the earlier scenarios' plans flushed
    earlier = trajectories(system.recordings()[-1])
    calls = traffic_calls(good, RECORDER, count)
    phases = kill_and_restart(system, traffic, calls, RECORDER, settle=FLUSH_ALLOWANCE)
    tally.add(phases.all())
    time.sleep(FLUSH_WAIT)
    killed_file, new_file = system.recordings()[-2:]
    kept, new = trajectories(killed_file) - earlier, trajectories(new_file)
    planned = all(r.outcome is Outcome.SUCCEEDED for r in tally.results)
    before = sum(r.outcome is Outcome.SUCCEEDED for r in phases.settled)
    after = sum(r.outcome is Outcome.SUCCEEDED for r in phases.after)
    tally.facts = {
        "all_planned": planned,
        "killed_file": kept,
        "planned_before": before,
        "flush_allowance_s": FLUSH_ALLOWANCE,
        "new_file": new,
        "planned_after": after,
        "recovered": not phases.missing,
        "down_s": round(phases.down_s, 2),
        "missing": phases.missing,
        "note": f"plans {'all' if planned else 'NOT all'} succeeded; killed file "
        f"readable with {kept} of its trajectories (it must hold the {before} "
        f"answered {FLUSH_ALLOWANCE:g} s or more before the kill), the new one "
        f"has {new} of the {after} planned after the restart",
    }
    tally.crashes = system.crashes()
    return tally
