"""Every key armplan's services answer or publish, relative to the namespace.

With the default namespace ``armplan`` the planner answers ``armplan/plan``
(the SPEC's outside contract) and IK answers ``armplan/ik/solve``. Routes
marked TODO have message types chosen before their algorithms existed; the
lead confirms them when wiring the services.
"""

from __future__ import annotations

from typing import Any

from shared.bus.route import NoArguments, OpaqueMessage, Route
from shared.messages import (
    Decision,
    IKRequest,
    IKResult,
    JointPath,
    PlanRequest,
    Trajectory,
    WristPath,
)

#: One posture: target in, joint angles out (``services.ik.solve_request``).
IK_SOLVE = Route("ik", "ik/solve", IKRequest, IKResult)
#: The public entry point: a task in, one trajectory out.
PLAN = Route("planner", "plan", PlanRequest, Trajectory)
#: Motion decision along a wrist path. TODO(lead): confirm the messages.
DECIDE = Route("decide", "decide", WristPath, Decision)
#: Ruckig time-parameterisation. TODO(lead): confirm the messages.
TIMING = Route("timing", "timing", JointPath, Trajectory)
#: The current motion model. TODO(lead): a model message in shared/messages.
FIT_MODEL = Route("fit", "fit/model", NoArguments, OpaqueMessage)

#: Every route, in the order ``armplan up`` starts their services.
ROUTES: tuple[Route[Any, Any], ...] = (FIT_MODEL, DECIDE, IK_SOLVE, TIMING, PLAN)

#: Where the planner publishes each finished trajectory (``Trajectory``).
TRAJECTORY_TOPIC = "plan/trajectory"
#: Where the fit service publishes each newly fitted model.
MODEL_TOPIC = "fit/model/update"
