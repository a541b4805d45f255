"""Valid requests for every route: traffic, templates for bad inputs, probes.

The stage requests (decide, ik/path, timing) are the very ones the planner
sends for a one-second reach: the reach is planned here, in-process, with
stages that keep what they are asked. The bridge's request plays a
trajectory that holds the arm still at rest for 0.2 s, so it is quick.
"""

from __future__ import annotations

from typing import Any, NamedTuple

from armplan.faults.outcome import Call
from services.planner.keeping_stages import KeepingStages
from services.planner.pipeline import plan
from shared.bus import NoArguments, Route
from shared.bus.robot_routes import EXECUTE
from shared.bus.routes import DECIDE, FIT, FIT_MODEL, IK_SOLVE, PLAN, TIMING
from shared.demos.nao_grid import nao_grid
from shared.messages import (
    ExecuteRequest,
    FitRequest,
    IKRequest,
    Message,
    PlanRequest,
    Trajectory,
)

#: The reach every template comes from: a one-second reach, right arm [m].
REACH = (0.12, -0.10, 0.05)
#: Samples of the still trajectory the bridge plays, 0.1 s apart.
STILL_SAMPLES = 3


def still(trajectory: Trajectory, samples: int = STILL_SAMPLES) -> Trajectory:
    """``trajectory``'s first sample held for ``samples`` samples, 0.1 s apart."""
    zero = [0.0] * len(trajectory.joint_names)
    return trajectory.model_copy(
        update={
            "times": [0.1 * k for k in range(samples)],
            "positions": [trajectory.positions[0]] * samples,
            "velocities": [zero] * samples,
            "accelerations": [zero] * samples,
            "primitives": [trajectory.primitives[0]] * samples,
            "wrist_path": [trajectory.wrist_path[0]] * samples,
        }
    )


class GoodRequests(NamedTuple):
    """A valid request per route, and the cheap one that shows a service works.

    Attributes:
        by_route: A valid request for each route's path (``"plan"``,
            ``"bridge/execute"``...); fit's names a file that is not there,
            so it is valid but refused.
        plans: Plan requests for traffic: reaches to NAO's 16 grid targets.
    """

    by_route: dict[str, Message]
    plans: list[PlanRequest]

    def probe(self, service: str) -> Call:
        """A request ``service`` answers with a result, quickly."""
        routes: dict[str, Route[Any, Any]] = {
            "fit": FIT_MODEL,
            "decide": DECIDE,
            "ik": IK_SOLVE,
            "timing": TIMING,
            "planner": PLAN,
            "bridge": EXECUTE,
        }
        route = routes[service]
        return Call(route, self.by_route[route.path])

    def plan_calls(self) -> list[Call]:
        """One plan call per grid target."""
        return [Call(PLAN, request) for request in self.plans]


def good_requests() -> GoodRequests:
    """Plan the reach in-process and keep every request made on the way."""
    reach = PlanRequest.model_validate({"targets": [{"position": REACH}]})
    stages = KeepingStages()
    trajectory = plan(reach, stages).trajectory
    by_route: dict[str, Message] = {
        FIT_MODEL.path: NoArguments(),
        FIT.path: FitRequest(files=["faults-no-such-demo.mcap"]),
        IK_SOLVE.path: IKRequest(target=REACH),
        PLAN.path: reach,
        EXECUTE.path: ExecuteRequest(trajectory=still(trajectory)),
        **stages.asked,
    }
    plans = [
        PlanRequest.model_validate({"targets": [{"position": tuple(t.wrist)}]})
        for t in nao_grid()
    ]
    return GoodRequests(by_route, plans)
