"""Inverse kinematics per movement primitive (paper Section IV) and baselines.

The algorithm lives here; ``service.py`` (added with the Zenoh services) is a
thin wrapper that serves it.
"""

from services.ik.solver import (
    IKSolution,
    check_reachable,
    check_target,
    solve,
    solve_request,
)

__all__ = ["IKSolution", "check_reachable", "check_target", "solve", "solve_request"]
