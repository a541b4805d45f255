"""The IK service: one posture, or a reach's joint path, on Zenoh.

Keys (namespace ``armplan`` by default):
    ``armplan/ik/solve``  IKRequest -> IKResult (``services.ik.solve_request``)
    ``armplan/ik/path``   PathIKRequest -> JointPath (the planner's ik stage,
                          ``services.planner.stages.path_ik``)

Run it with ``python -m services.ik`` (``armplan up`` does). It calls no
other service; errors go back as typed ``reply_err`` (``shared.bus``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from services.ik.solver import solve_request
from services.planner.stages import path_ik
from shared.bus import Bus, Endpoint
from shared.bus.routes import IK_PATH, IK_SOLVE
from shared.messages import IKRequest, IKResult
from shared.robot import load_arm

NAME = "ik"


def solve(request: IKRequest) -> IKResult:
    """One posture, exactly as ``armplan ik`` computes it in-process."""
    return solve_request(load_arm(request.arm), request)


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The IK service's endpoints (it calls no other service)."""
    return [Endpoint(IK_SOLVE, solve), Endpoint(IK_PATH, path_ik)]
