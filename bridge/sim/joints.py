"""The simulated NAO's joints and their limits, read from the robot description."""

from __future__ import annotations

from functools import cache
from typing import NamedTuple

import pinocchio as pin

from bridge.sim.errors import SimCommandError
from shared.robot import JOINTS, Side
from shared.robot.arm_model import urdf_text


class JointSpec(NamedTuple):
    """One joint of the simulated NAO.

    Attributes:
        name: NAO joint name, e.g. ``RShoulderPitch`` or ``RHand``.
        lower: Lower limit [rad] (hands: open fraction 0).
        upper: Upper limit [rad] (hands: open fraction 1).
        velocity: Speed limit [rad/s] (hands: fraction per second).
        effort: Torque limit [N m].
    """

    name: str
    lower: float
    upper: float
    velocity: float
    effort: float


@cache
def joint_specs() -> dict[str, JointSpec]:
    """Every joint of the robot description (both arms and hands), by name."""
    model = pin.buildModelFromXML(urdf_text())
    specs = {}
    for jid in range(1, model.njoints):
        name, joint = model.names[jid], model.joints[jid]
        specs[name] = JointSpec(
            name,
            float(model.lowerPositionLimit[joint.idx_q]),
            float(model.upperPositionLimit[joint.idx_q]),
            float(model.velocityLimit[joint.idx_v]),
            float(model.effortLimit[joint.idx_v]),
        )
    return specs


def _chain(side: Side) -> list[str]:
    return [side.prefix + joint for joint in JOINTS] + [side.hand_joint]


#: NAOqi chain names the simulated NAO knows. It has arms only: "Body" and
#: "Joints" are its twelve arm and hand joints.
CHAINS: dict[str, list[str]] = {
    "RArm": _chain(Side.RIGHT),
    "LArm": _chain(Side.LEFT),
    "Body": _chain(Side.LEFT) + _chain(Side.RIGHT),
    "Joints": _chain(Side.LEFT) + _chain(Side.RIGHT),
}


def expand_names(names: str | list[str]) -> list[str]:
    """Joint names from a joint name, a chain name, or a list of them.

    Raises:
        SimCommandError: naming a joint or chain the robot does not have.
    """
    items = [names] if isinstance(names, str) else list(names)
    if not items:
        raise SimCommandError("no joint names given")
    known = joint_specs()
    joints: list[str] = []
    for item in items:
        if item in CHAINS:
            joints += CHAINS[item]
        elif item in known:
            joints.append(item)
        else:
            raise SimCommandError(
                f"unknown joint or chain {item!r}; this NAO has "
                + ", ".join([*CHAINS, *known])
            )
    return joints
