"""The bridge starts no movement for a caller whose session has ended.

A real router, the simulated NAO over libqi, the bridge service and a
caller in a process of its own, asking ``bridge/execute`` for a trajectory
that starts away from the arm: the bridge moves the arm to the start first
(the approach). The caller is killed during the approach. The bridge used
to play the trajectory all the same, for no one (its caller had given 60
s, well past the movement's end); its caller token has gone with its
session, so after the approach nothing of the trajectory is sent.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path
from typing import TYPE_CHECKING

from test_bridge_stop_query import _wait, served

from bridge.minimum_jerk import minimum_jerk_trajectory
from shared.robot.postures import forward, rest

if TYPE_CHECKING:
    from bridge.sim import SimProcess

#: The caller: one execute query, waiting 60 s for its answer.
CALLER = textwrap.dedent(
    """
    import sys
    from pathlib import Path
    from shared.bus import Bus, load_config
    from shared.bus.robot_routes import EXECUTE
    from shared.messages import ExecuteRequest, Trajectory

    trajectory = Trajectory.model_validate_json(Path(sys.argv[2]).read_text())
    with Bus.connect(load_config(endpoints=(sys.argv[1],))) as bus:
        bus.call(EXECUTE, ExecuteRequest(trajectory=trajectory), timeout=60.0)
    """
)


def test_a_caller_killed_during_the_approach_gets_no_trajectory_played(
    tmp_path: Path, sim: SimProcess
) -> None:
    # from the arm stretched forward back to rest: the sim's arm rests, so
    # the bridge first approaches the stretched arm
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [2.0]
    )
    path = tmp_path / "trajectory.json"
    path.write_text(trajectory.to_json())
    with served(tmp_path, sim) as there:
        caller = subprocess.Popen(
            [sys.executable, "-c", CALLER, there.bus.config.endpoint, str(path)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        try:
            _wait("the approach", lambda: there.sim_calls("angleInterpolation") == 1)
            _wait("a state of the approach", lambda: len(there.states) > 2)
        finally:
            caller.send_signal(signal.SIGKILL)
            caller.communicate(timeout=30.0)
        _wait("the execution's outcome", lambda: len(there.outcomes) == 1, 30.0)
        time.sleep(1.0)  # nothing more is sent
        assert there.sim_calls("angleInterpolation") == 1  # the approach only
    outcome = there.outcomes[0]
    assert (outcome.outcome, outcome.error_kind) == ("error", "caller_deadline")
    assert outcome.message is not None
    assert "the caller's session ended (interrupted or killed)" in outcome.message
