"""The IK service: ``services.ik.solve_request`` on Zenoh, and nothing more.

Keys (namespace ``armplan`` by default):
    ``armplan/ik/solve``  IKRequest -> IKResult (or an ErrorReply)

Run it with ``python -m services.ik`` (``armplan up`` does). TODO(lead): the
SPEC's "joint path for a decided wrist path" route (``ik/path``, calling
``services.ik.track.track_path`` with the decisions) needs a request message
in ``shared/messages`` (wrist path + decisions + start posture + method).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from services.ik.solver import solve_request
from shared.bus import Bus, Endpoint
from shared.bus.routes import IK_SOLVE
from shared.messages import IKRequest, IKResult
from shared.robot import load_arm

NAME = "ik"


def solve(request: IKRequest) -> IKResult:
    """One posture, exactly as ``armplan ik`` computes it in-process."""
    return solve_request(load_arm(request.arm), request)


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The IK service's endpoints (it calls no other service)."""
    return [Endpoint(IK_SOLVE, solve)]
