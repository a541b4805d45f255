"""The robot side's keys on Zenoh: the bridge's route, relative to the namespace.

With the default namespace ``armplan``:

- ``armplan/bridge/execute``: an ``ExecuteRequest`` (a trajectory) in, the
  ``ExecuteReply`` (executed states and the tracking report) out;
- ``armplan/bridge/stop``: any payload (a ``StopRequest``: ``{}``, perhaps
  a reason; read leniently) in: the movement playing is stopped as the
  query arrives, whatever its payload or deadline (``Endpoint.at_once``),
  the follower's waiting trajectories dropped; the ``StopReply`` (what was
  stopped, where, whether the arm is known still) comes once the stopped
  execution has ended. It has a worker of its own, so it is answered
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
#: Stop the movement playing now; answered once it has ended.
STOP = Route(BRIDGE, "bridge/stop", StopRequest, StopReply)
