"""Every key armplan's services answer or publish, relative to the namespace.

With the default namespace ``armplan`` the planner answers ``armplan/plan``
(the SPEC's outside contract) and IK answers ``armplan/ik/solve``. The
planner's stages answer the request messages of ``shared.messages.stages``
with the results of the in-process stage functions
(``services.planner.stages``), so a plan made through the services equals
one made in-process.

Routes whose answer depends on the request alone are ``repeatable``: a
caller asks them again if no answer comes in ``resend_after`` seconds. The
planner is not (each plan is published), nor is a fit (it replaces the
served model).
"""

from __future__ import annotations

from typing import Any

from shared.bus.route import NoArguments, Route
from shared.messages import (
    DecideRequest,
    Decision,
    FitRequest,
    IKRequest,
    IKResult,
    JointPath,
    MotionModel,
    PathIKRequest,
    PlanRequest,
    TimingRequest,
    Trajectory,
)

#: One posture: target in, joint angles out (``services.ik.solve_request``).
IK_SOLVE = Route("ik", "ik/solve", IKRequest, IKResult, repeatable=True)
#: A reach's joint path along its wrist path (``services.planner.stages.path_ik``).
IK_PATH = Route("ik", "ik/path", PathIKRequest, JointPath, repeatable=True)
#: The public entry point: a task in, one trajectory out.
PLAN = Route("planner", "plan", PlanRequest, Trajectory)
#: Motion decision along a wrist path (``services.planner.stages.decide``).
DECIDE = Route("decide", "decide", DecideRequest, Decision, repeatable=True)
#: Ruckig time-parameterisation of a task's joint paths (``timing_stage.timing``).
TIMING = Route("timing", "timing", TimingRequest, Trajectory, repeatable=True)
#: The motion model the fit service serves now.
FIT_MODEL = Route("fit", "fit/model", NoArguments, MotionModel, repeatable=True)
#: Fit a new model to demonstration files; it is served and published.
FIT = Route("fit", "fit", FitRequest, MotionModel)

#: Every route, in the order ``armplan up`` starts their services.
ROUTES: tuple[Route[Any, Any], ...] = (
    FIT_MODEL,
    FIT,
    DECIDE,
    IK_SOLVE,
    IK_PATH,
    TIMING,
    PLAN,
)

#: Where the planner publishes each finished trajectory (``Trajectory``).
TRAJECTORY_TOPIC = "plan/trajectory"
#: Where the fit service publishes each new model (``MotionModel``).
MODEL_TOPIC = "fit/model/update"
