"""The robot side's keys on Zenoh: the bridge's route, relative to the namespace.

With the default namespace ``armplan``:

- ``armplan/bridge/execute``: an ``ExecuteRequest`` (a trajectory) in, the
  ``ExecuteReply`` (executed states and the tracking report) out;
- ``armplan/bridge/stop``: a ``StopRequest`` (``{}``, perhaps a reason) in:
  the movement playing is stopped at once, the follower's waiting
  trajectories dropped; the ``StopReply`` (what was stopped, where) comes
  once the arm is still. It has a worker of its own, so it is answered
  while an execute query blocks (``Endpoint.own_worker``);
- the bridge publishes on ``bridge/frames``, ``bridge/state`` and
  ``bridge/report`` (``shared.bus.topics``).

The bridge process is ``python -m bridge.serve``; it is not among the
planner's services (``routes.ROUTES``) because it needs a robot.
"""

from __future__ import annotations

from shared.bus.route import Route
from shared.messages import ExecuteReply, ExecuteRequest, StopReply, StopRequest

#: The bridge's service name (its liveliness token ``<ns>/alive/bridge``).
BRIDGE = "bridge"
#: Play a trajectory on the robot and answer with what it did.
EXECUTE = Route(BRIDGE, "bridge/execute", ExecuteRequest, ExecuteReply)
#: Stop the movement playing now; answered once the arm is still.
STOP = Route(BRIDGE, "bridge/stop", StopRequest, StopReply)
