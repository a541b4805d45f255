"""The ikpy peer: IK of a wrist path's points with ikpy, on the project's URDF.

The chain is read by ikpy from ``shared/robot/nao_arms.urdf``, torso to the
WristYaw joint's origin (the SPEC's "wrist"), so both sides solve the same
kinematics; the tests check the two forward kinematics agree. The four
joints that move the wrist (shoulder pitch and roll, elbow yaw and roll) are
active, within the URDF's ranges; WristYaw does not move the wrist and is
locked. Each point is solved with ``Chain.inverse_kinematics`` (ikpy's
defaults: position only, scipy least squares) from the previous point's
solution, as a user without armplan would follow a path.
"""

from __future__ import annotations

from importlib import resources
from typing import Any

import numpy as np

from armplan.bench.extras import require
from shared.robot.arm_model import URDF_RESOURCE, ArmModel

#: Which of the chain's links move: ikpy's origin link, the four joints that
#: move the wrist, and WristYaw (locked).
ACTIVE = [False, True, True, True, True, False]
#: A point counts as reached within this distance [m].
REACHED = 1e-4


def wrist_chain(arm: ArmModel) -> Any:
    """ikpy's chain of ``arm`` from the torso to the wrist (an ``ikpy.chain.Chain``).

    Raises:
        ArmplanError: if ikpy is not installed (it comes with the dev extra).
    """
    require("ikpy")
    from ikpy.chain import Chain
    from ikpy.urdf.URDF import get_chain_from_joints

    urdf = resources.files("shared.robot").joinpath(URDF_RESOURCE)
    with resources.as_file(urdf) as path:
        elements = get_chain_from_joints(str(path), list(arm.joint_names))
        full = Chain.from_urdf_file(
            str(path),
            base_elements=elements,
            active_links_mask=[*ACTIVE, False],  # and the hand, beyond the wrist
            symbolic=False,
        )
    # ikpy follows the URDF on past the wrist to the hand: keep up to WristYaw.
    return Chain(full.links[: len(ACTIVE)], active_links_mask=ACTIVE)


def wrist_of(chain: Any, q: np.ndarray) -> np.ndarray:
    """The wrist position [m], shape (3,), of joint angles ``q`` [rad], shape (5,)."""
    return chain.forward_kinematics(np.concatenate(([0.0], q)))[:3, 3]


def ikpy_track(chain: Any, positions: np.ndarray, start: np.ndarray) -> np.ndarray:
    """ikpy's joint angles [rad], shape (n, 5), for wrist points [m], shape (n, 3).

    Each point starts from the solution of the point before (the first from
    ``start`` [rad], shape (5,)).
    """
    x = np.concatenate(([0.0], start))
    out = np.empty((len(positions), len(start)))
    for k, point in enumerate(positions):
        x = chain.inverse_kinematics(point, initial_position=x)
        out[k] = x[1:]
    return out


def reached_fraction(chain: Any, q: np.ndarray, positions: np.ndarray) -> float:
    """Fraction of points whose wrist is within ``REACHED`` of its target."""
    errors = [
        np.linalg.norm(wrist_of(chain, row) - point)
        for row, point in zip(q, positions, strict=True)
    ]
    return float(np.mean(np.array(errors) < REACHED))
