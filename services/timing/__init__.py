"""Time parameterisation: IK joint paths to jerk-limited trajectories with Ruckig.

The algorithm lives here, apart from any Zenoh wrapper, so the same code runs
in-process and as the ``timing`` service. The pipeline calls:

- :func:`time_path`: one joint path, at rest at both ends, fastest or with a
  human bell of a given duration.
- :func:`time_segments` / :func:`time_path_with_stops`: multi-target tasks
  (reach, hold, retreat) as one trajectory with rests between movements.
- :func:`reach_duration`: the human default duration of a move, scaled to NAO.
- :func:`time_given`: a path already timed by the caller (``--wrist-path``),
  derivatives and a limit check, no retiming.
- :func:`check_limits`: the safety check every trajectory passes (the robot
  bridge reuses it).
"""

from services.timing.check import check_limits, check_path, check_times
from services.timing.given_times import time_given
from services.timing.human_duration import human_duration, reach_duration
from services.timing.segments import Segment, time_path_with_stops, time_segments
from services.timing.time_path import RATE, time_path
from services.timing.trajectory import TimedTrajectory

__all__ = [
    "RATE",
    "Segment",
    "TimedTrajectory",
    "check_limits",
    "check_path",
    "check_times",
    "human_duration",
    "reach_duration",
    "time_given",
    "time_path",
    "time_path_with_stops",
    "time_segments",
]
