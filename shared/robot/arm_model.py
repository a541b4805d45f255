"""One NAO arm as a pinocchio model loaded from the project's URDF.

The URDF (``nao_arms.urdf``) holds the torso and both arms. ``load_arm`` reads
it with pinocchio and keeps one arm: the other arm's joints and the gripper
(open fraction) are locked at zero, which leaves a 5-joint chain whose
configuration is ordered as the paper's "joint 1..5" (ShoulderPitch,
ShoulderRoll, ElbowYaw, ElbowRoll, WristYaw).

Points of the arm (all in the torso frame):
    shoulder: origin of ShoulderPitch.
    elbow: origin of ElbowYaw/ElbowRoll.
    wrist: origin of WristYaw.
    hand: the gripper frame, (0.05775, 0, -0.01231) m beyond the wrist.
"""

from __future__ import annotations

import math
from functools import cache
from importlib import resources
from typing import NamedTuple

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from shared.robot.limits import JointLimits
from shared.robot.side import JOINTS, Side

#: The robot description inside the package.
URDF_RESOURCE = "nao_arms.urdf"

#: Which arm links make the paper's "upper arm" and "lower arm" (eq. 16).
UPPER_ARM_JOINTS = ("ShoulderPitch", "ShoulderRoll")
LOWER_ARM_JOINTS = ("ElbowYaw", "ElbowRoll", "WristYaw")


def urdf_text() -> str:
    """The project's robot description (URDF XML)."""
    return resources.files("shared.robot").joinpath(URDF_RESOURCE).read_text()


class ArmPoints(NamedTuple):
    """Positions of the arm's key points in the torso frame [m], each shape (3,)."""

    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray
    hand: np.ndarray


class SegmentComs(NamedTuple):
    """Centres of mass of the upper and lower arm (eq. 16).

    Attributes:
        upper: Upper-arm centre of mass in the torso frame [m], shape (3,).
        lower: Lower-arm (forearm and hand) centre of mass [m], shape (3,).
        upper_mass: Upper-arm mass m_u [kg].
        lower_mass: Lower-arm mass m_l [kg].
    """

    upper: np.ndarray
    lower: np.ndarray
    upper_mass: float
    lower_mass: float

    @property
    def heights(self) -> tuple[float, float]:
        """Heights h_u, h_l of the two centres of mass above the torso origin [m]."""
        return float(self.upper[2]), float(self.lower[2])


class Kinematics(NamedTuple):
    """Everything the solvers need about one posture, from one pinocchio pass.

    Attributes:
        q: Joint angles [rad], shape (5,).
        shoulder, elbow, wrist, hand: Point positions [m], shape (3,).
        wrist_rotation: Orientation of the wrist frame in the torso frame, (3, 3).
        elbow_jacobian: d(elbow)/dq [m/rad], shape (3, 5).
        wrist_jacobian: d(wrist)/dq [m/rad], shape (3, 5).
        wrist_angular_jacobian: Angular velocity of the wrist frame per joint
            speed, in torso axes [rad/s per rad/s], shape (3, 5).
        gravity_energy: Gravitational potential energy of the arm's links
            above the torso origin [J].
        gravity_gradient: d(gravity_energy)/dq [J/rad], shape (5,).
    """

    q: np.ndarray
    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray
    hand: np.ndarray
    wrist_rotation: np.ndarray
    elbow_jacobian: np.ndarray
    wrist_jacobian: np.ndarray
    wrist_angular_jacobian: np.ndarray
    gravity_energy: float
    gravity_gradient: np.ndarray


class ArmModel:
    """Kinematics and gravity of one NAO arm (5 joints), backed by pinocchio.

    Build it with :func:`load_arm`. Methods take joint angles ``q`` [rad],
    shape (5,), in the paper's order, and return values in the torso frame.
    One instance is not thread-safe (it reuses one pinocchio data buffer);
    make one per thread with ``load_arm(side).copy()``.
    """

    def __init__(self, side: Side, model: pin.Model) -> None:
        self.side = side
        self.model = model
        self._data: pin.Data | None = None
        names = side.joint_names
        self._frames = {
            "shoulder": model.getFrameId(names[0]),
            "elbow": model.getFrameId(names[2]),
            "wrist": model.getFrameId(names[4]),
            "hand": model.getFrameId(("r" if side is Side.RIGHT else "l") + "_gripper"),
        }
        self._joint_ids = [model.getJointId(name) for name in names]
        self.limits = JointLimits(
            names=names,
            lower=model.lowerPositionLimit.copy(),
            upper=model.upperPositionLimit.copy(),
            velocity=model.velocityLimit.copy(),
            effort=model.effortLimit.copy(),
        )
        for array in self.limits[1:]:
            array.setflags(write=False)
        self.reach = _reach_of(side, self)

    @property
    def data(self) -> pin.Data:
        """The pinocchio data buffer of this instance, made on first use."""
        if self._data is None:
            self._data = self.model.createData()
        return self._data

    def copy(self) -> ArmModel:
        """An independent instance (own data buffer) of the same arm."""
        return ArmModel(self.side, self.model)

    @property
    def frame_ids(self) -> dict[str, int]:
        """The pinocchio frame of each key point (``ArmPoints``' fields)."""
        return dict(self._frames)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """NAO names of the five joints, e.g. ``RShoulderPitch``."""
        return self.limits.names

    @property
    def upper_arm_length(self) -> float:
        """Shoulder-to-elbow distance L_u [m] (NAO's elbow is offset 15 mm)."""
        return float(np.linalg.norm(self.elbow_offset))

    @property
    def shoulder_position(self) -> np.ndarray:
        """ShoulderPitch's origin in the torso frame [m], shape (3,)."""
        return self.model.jointPlacements[self._joint_ids[0]].translation.copy()

    @property
    def elbow_offset(self) -> np.ndarray:
        """Elbow origin in the ShoulderRoll frame [m], shape (3,)."""
        return self.model.jointPlacements[self._joint_ids[2]].translation.copy()

    @property
    def forearm_length(self) -> float:
        """Elbow-to-wrist distance L_f [m]."""
        return float(
            np.linalg.norm(self.model.jointPlacements[self._joint_ids[4]].translation)
        )

    @property
    def hand_offset(self) -> np.ndarray:
        """Gripper frame in the wrist frame [m], shape (3,)."""
        return self.model.frames[self._frames["hand"]].placement.translation.copy()

    def _update(self, q: np.ndarray) -> None:
        pin.forwardKinematics(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)

    def _position(self, frame: str) -> np.ndarray:
        return self.data.oMf[self._frames[frame]].translation.copy()

    def fk(self, q: np.ndarray) -> ArmPoints:
        """Shoulder, elbow, wrist and hand positions [m] for angles ``q`` [rad] (5,)."""
        self._update(np.asarray(q, dtype=float))
        return ArmPoints(*(self._position(name) for name in ArmPoints._fields))

    def jacobian(self, q: np.ndarray, point: str) -> np.ndarray:
        """Linear Jacobian d(point)/dq [m/rad], shape (3, 5).

        Args:
            q: Joint angles [rad], shape (5,).
            point: ``"shoulder"``, ``"elbow"``, ``"wrist"`` or ``"hand"``.
        """
        return self.frame_jacobian(q, point)[:3]

    def frame_jacobian(self, q: np.ndarray, point: str) -> np.ndarray:
        """Spatial Jacobian of a point's frame, torso-aligned axes, shape (6, 5).

        Rows 0-2: linear velocity [m/s per rad/s]; rows 3-5: angular velocity.
        """
        q = np.asarray(q, dtype=float)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        return pin.getFrameJacobian(
            self.model, self.data, self._frames[point], pin.LOCAL_WORLD_ALIGNED
        )

    def rotation(self, q: np.ndarray, point: str) -> np.ndarray:
        """Orientation of a point's frame in the torso frame, shape (3, 3)."""
        self._update(np.asarray(q, dtype=float))
        return self.data.oMf[self._frames[point]].rotation.copy()

    def segment_coms(self, q: np.ndarray) -> SegmentComs:
        """Centres of mass of upper and lower arm (eq. 16) for angles ``q`` [rad]."""
        self._update(np.asarray(q, dtype=float))
        upper, upper_mass = self._segment(UPPER_ARM_JOINTS)
        lower, lower_mass = self._segment(LOWER_ARM_JOINTS)
        return SegmentComs(upper, lower, upper_mass, lower_mass)

    def _segment(self, joints: tuple[str, ...]) -> tuple[np.ndarray, float]:
        """(centre of mass [m], mass [kg]) of the links moved by ``joints``."""
        total, moment = 0.0, np.zeros(3)
        for joint in joints:
            jid = self.model.getJointId(self.side.prefix + joint)
            inertia = self.model.inertias[jid]
            moment += inertia.mass * self.data.oMi[jid].act(inertia.lever)
            total += inertia.mass
        return moment / total, total

    def gravity_energy(self, q: np.ndarray) -> float:
        """Gravitational potential energy of the arm's links [J] (eq. 16)."""
        return float(
            pin.computePotentialEnergy(self.model, self.data, np.asarray(q, float))
        )

    def gravity_gradient(self, q: np.ndarray) -> np.ndarray:
        """d(gravity_energy)/dq, the gravity torques [J/rad = N m], shape (5,)."""
        return pin.computeGeneralizedGravity(
            self.model, self.data, np.asarray(q, float)
        ).copy()

    def kinematics(self, q: np.ndarray) -> Kinematics:
        """All positions, Jacobians and gravity terms for ``q`` [rad], in one pass."""
        q = np.asarray(q, dtype=float)
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        frames = self._frames
        wrist_j = pin.getFrameJacobian(
            model, data, frames["wrist"], pin.LOCAL_WORLD_ALIGNED
        )
        elbow_j = pin.getFrameJacobian(
            model, data, frames["elbow"], pin.LOCAL_WORLD_ALIGNED
        )
        energy = float(pin.computePotentialEnergy(model, data, q))
        gradient = pin.computeGeneralizedGravity(model, data, q).copy()
        return Kinematics(
            q=q,
            shoulder=self._position("shoulder"),
            elbow=self._position("elbow"),
            wrist=self._position("wrist"),
            hand=self._position("hand"),
            wrist_rotation=data.oMf[frames["wrist"]].rotation.copy(),
            elbow_jacobian=elbow_j[:3],
            wrist_jacobian=wrist_j[:3],
            wrist_angular_jacobian=wrist_j[3:],
            gravity_energy=energy,
            gravity_gradient=gradient,
        )

    def wrist_distance(
        self, elbow_yaw: npt.ArrayLike, elbow_roll: npt.ArrayLike
    ) -> np.ndarray:
        """Shoulder-to-wrist distance [m] at these ElbowYaw and ElbowRoll [rad].

        Only these two joints change it (the elbow is offset from the upper
        arm's axis by u, the forearm is L_f long):
        d^2 = |u|^2 + L_f^2 + 2 L_f (u_x cos th4 + u_y cos th3 sin th4).
        The arguments broadcast as numpy arrays; so does the result.
        """
        ey, er = np.asarray(elbow_yaw, dtype=float), np.asarray(elbow_roll, dtype=float)
        u, lf = self.elbow_offset, self.forearm_length
        d2 = (
            u @ u
            + lf**2
            + 2 * lf * (u[0] * np.cos(er) + u[1] * np.cos(ey) * np.sin(er))
        )
        return np.sqrt(d2)

    def distance_span_at(self, elbow_roll: float) -> tuple[float, float]:
        """Shoulder-to-wrist distances [m] that ElbowYaw reaches: (least, most).

        ElbowRoll is held at ``elbow_roll`` [rad], ElbowYaw goes anywhere in
        its range. The squared distance is affine in cos(ElbowYaw) (``wrist_distance``),
        so its extremes lie at the ends of ElbowYaw's range or where ElbowYaw
        is a multiple of pi: the span is exact, not sampled.
        """
        low, high = self.limits.lower[2], self.limits.upper[2]
        turns = np.arange(math.ceil(low / math.pi), math.floor(high / math.pi) + 1)
        d = self.wrist_distance(np.append([low, high], turns * math.pi), elbow_roll)
        return float(d.min()), float(d.max())

    def _distance_span(self) -> tuple[float, float]:
        """Smallest and largest shoulder-to-wrist distance within the limits [m].

        A dense grid over ElbowYaw and ElbowRoll (``wrist_distance``).
        """
        ey = np.linspace(self.limits.lower[2], self.limits.upper[2], 181)[:, None]
        er = np.linspace(self.limits.lower[3], self.limits.upper[3], 181)[None, :]
        d = self.wrist_distance(ey, er)
        return float(d.min()), float(d.max())


def _build(side: Side) -> pin.Model:
    """The 5-joint pinocchio model of one arm, other joints locked at 0."""
    full = pin.buildModelFromXML(urdf_text())
    keep = set(side.joint_names)
    lock = [full.getJointId(name) for name in full.names[1:] if name not in keep]
    model = pin.buildReducedModel(full, lock, pin.neutral(full))
    order = [model.names[i] for i in range(1, model.njoints)]
    if tuple(order) != side.joint_names:
        raise RuntimeError(f"unexpected joint order in the robot description: {order}")
    return model


_REACH: dict[Side, tuple[float, float]] = {}


def _reach_of(side: Side, arm: ArmModel) -> tuple[float, float]:
    """The arm's distance span, computed once per side."""
    if side not in _REACH:
        _REACH[side] = arm._distance_span()
    return _REACH[side]


@cache
def _model(side: Side) -> pin.Model:
    return _build(side)


def load_arm(side: Side | str) -> ArmModel:
    """The arm model of ``side`` (``"right"``/``"left"``), loaded from the URDF.

    The parsed pinocchio model is cached; each call returns a new ``ArmModel``
    with its own data buffer.
    """
    side = Side.parse(side)
    return ArmModel(side, _model(side))


__all__ = ["JOINTS", "ArmModel", "ArmPoints", "Kinematics", "SegmentComs", "load_arm"]
