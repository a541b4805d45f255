"""Forward kinematics, Jacobians and gravity of one arm, on floats.

The numbers come from the pinocchio model of ``shared.robot`` (hence from
the URDF, once): each joint's origin in its parent, its axis, and the mass
and centre of mass of the link it moves. Every joint of NAO's arm turns
about a principal axis of its parent's frame with no fixed rotation in
between, which is what this code relies on (checked when a Chain is built).
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import numpy as np

from services.ik.kernel.small import Vec
from shared.robot.arm_model import ArmModel, load_arm
from shared.robot.side import Side

Matrix = tuple[Vec, Vec, Vec]
_AXES = {"JointModelRX": 0, "JointModelRY": 1, "JointModelRZ": 2}


def _turn(r: Matrix, axis: int, c: float, s: float) -> Matrix:
    """R @ Rot(axis, angle) for cos c and sin s of the angle (rows of R)."""
    (a, b, e), (d, f, g), (h, i, j) = r
    if axis == 0:
        return ((a, b * c + e * s, e * c - b * s), (d, f * c + g * s, g * c - f * s),
                (h, i * c + j * s, j * c - i * s))  # fmt: skip
    if axis == 1:
        return ((a * c - e * s, b, a * s + e * c), (d * c - g * s, f, d * s + g * c),
                (h * c - j * s, i, h * s + j * c))  # fmt: skip
    return ((a * c + b * s, b * c - a * s, e), (d * c + f * s, f * c - d * s, g),
            (h * c + i * s, i * c - h * s, j))  # fmt: skip


def _column(r: Matrix, axis: int) -> Vec:
    """Column ``axis`` of R (constant indices: compiled, no tuple is built)."""
    if axis == 0:
        return (r[0][0], r[1][0], r[2][0])
    if axis == 1:
        return (r[0][1], r[1][1], r[2][1])
    return (r[0][2], r[1][2], r[2][2])


def _apply(r: Matrix, v: Vec) -> Vec:
    return (
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    )


class ChainState:
    """One posture's kinematics: plain floats for the IK, numpy on demand.

    Float fields (used by the IK's hot loop):
        qf: Joint angles [rad], 5 floats.
        origins: Joint origins in the torso frame [m]: 0 shoulder, 2 elbow, 4 wrist.
        axes: Joint axes in the torso frame (unit), 5 vectors.
        rot: Orientation of the wrist frame, rows of a 3x3 matrix.
        jw: Columns of d(wrist)/dq [m/rad], 5 vectors.
        je: Columns of d(elbow)/dq [m/rad], 5 vectors (zero beyond ShoulderRoll).
        energy: Gravitational potential energy of the arm's links [J].
        grav: d(energy)/dq [J/rad], 5 floats.

    Numpy views with the names of ``shared.robot.Kinematics`` (q, shoulder,
    elbow, wrist, wrist_rotation, wrist_jacobian, elbow_jacobian,
    wrist_angular_jacobian, gravity_energy, gravity_gradient) are built on
    first access, so code written for Kinematics reads a ChainState too.
    """

    __slots__ = ("_cache", "axes", "energy", "grav", "je", "jw", "origins", "qf", "rot")

    def __init__(
        self,
        qf: tuple[float, float, float, float, float],
        origins: list[Vec],
        axes: list[Vec],
        rot: Matrix,
        jw: list[Vec],
        je: list[Vec],
        energy: float,
        grav: list[float],
    ) -> None:
        self.qf, self.origins, self.axes, self.rot = qf, origins, axes, rot
        self.jw, self.je, self.energy, self.grav = jw, je, energy, grav
        self._cache: dict[str, np.ndarray] = {}

    @property
    def p_shoulder(self) -> Vec:
        """Shoulder position [m]."""
        return self.origins[0]

    @property
    def p_elbow(self) -> Vec:
        """Elbow position [m]."""
        return self.origins[2]

    @property
    def p_wrist(self) -> Vec:
        """Wrist position [m]."""
        return self.origins[4]

    def _array(self, name: str, value: object) -> np.ndarray:
        """``value`` as a numpy array, made once per name."""
        made: np.ndarray | None = self._cache.get(name)
        if made is None:
            made = self._cache[name] = np.array(value)
        return made

    @property
    def q(self) -> np.ndarray:
        """Joint angles [rad], shape (5,)."""
        return self._array("q", self.qf)

    @property
    def shoulder(self) -> np.ndarray:
        """Shoulder position [m], shape (3,)."""
        return self._array("shoulder", self.origins[0])

    @property
    def elbow(self) -> np.ndarray:
        """Elbow position [m], shape (3,)."""
        return self._array("elbow", self.origins[2])

    @property
    def wrist(self) -> np.ndarray:
        """Wrist position [m], shape (3,)."""
        return self._array("wrist", self.origins[4])

    @property
    def wrist_rotation(self) -> np.ndarray:
        """Orientation of the wrist frame, shape (3, 3)."""
        return self._array("rot", self.rot)

    @property
    def wrist_jacobian(self) -> np.ndarray:
        """d(wrist)/dq [m/rad], shape (3, 5)."""
        return self._array("jw", self.jw).T

    @property
    def elbow_jacobian(self) -> np.ndarray:
        """d(elbow)/dq [m/rad], shape (3, 5)."""
        return self._array("je", self.je).T

    @property
    def wrist_angular_jacobian(self) -> np.ndarray:
        """Joint axes in the torso frame, shape (3, 5)."""
        return self._array("ax", self.axes).T

    @property
    def gravity_gradient(self) -> np.ndarray:
        """d(energy)/dq [J/rad], shape (5,)."""
        return self._array("grav", self.grav)

    @property
    def gravity_energy(self) -> float:
        """Gravitational potential energy [J]."""
        return self.energy


class Chain:
    """The arm as a chain of principal-axis joints, evaluated on floats.

    Args:
        arm: The pinocchio arm model whose numbers the chain copies.

    Raises:
        ValueError: if a joint is not a principal-axis revolute joint with an
            unrotated placement (not the case for NAO's arm).
    """

    def __init__(self, arm: ArmModel) -> None:
        model = arm.model
        self.side = arm.side
        self.limits = arm.limits
        self.lower = [float(v) for v in arm.limits.lower]
        self.upper = [float(v) for v in arm.limits.upper]
        self.offsets: list[Vec] = []
        self.axis_index: list[int] = []
        self.links: list[tuple[float, Vec]] = []
        for jid in range(1, model.njoints):
            placement = model.jointPlacements[jid]
            shortname = model.joints[jid].shortname()
            if shortname not in _AXES or not np.allclose(placement.rotation, np.eye(3)):
                raise ValueError(f"{model.names[jid]} is not a principal-axis joint")
            tx, ty, tz = (float(v) for v in placement.translation)
            self.offsets.append((tx, ty, tz))
            self.axis_index.append(_AXES[shortname])
            inertia = model.inertias[jid]
            lx, ly, lz = (float(v) for v in inertia.lever)
            self.links.append((float(inertia.mass), (lx, ly, lz)))
        self.gravity = -float(model.gravity.linear[2])

    def state(self, q: Any) -> ChainState:
        """Kinematics of posture ``q`` [rad] (5 values)."""
        angles = [float(q[0]), float(q[1]), float(q[2]), float(q[3]), float(q[4])]
        r: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        px = py = pz = 0.0
        origins: list[Vec] = []
        axes: list[Vec] = []
        coms: list[Vec] = []
        for k in range(5):
            ox, oy, oz = self.offsets[k]
            (a, b, c), (d, e, f), (g, h, i) = r
            px, py, pz = (
                px + a * ox + b * oy + c * oz,
                py + d * ox + e * oy + f * oz,
                pz + g * ox + h * oy + i * oz,
            )
            ax = self.axis_index[k]
            r = _turn(r, ax, math.cos(angles[k]), math.sin(angles[k]))
            origins.append((px, py, pz))
            axes.append(_column(r, ax))
            lx, ly, lz = self.links[k][1]
            (a, b, c), (d, e, f), (g, h, i) = r
            coms.append(
                (
                    px + a * lx + b * ly + c * lz,
                    py + d * lx + e * ly + f * lz,
                    pz + g * lx + h * ly + i * lz,
                )
            )
        jw = _columns(axes, origins, origins[4], 5)
        je = _columns(axes, origins, origins[2], 2) + [(0.0, 0.0, 0.0)] * 3
        energy, grav = self._gravity(axes, origins, coms)
        qf = (angles[0], angles[1], angles[2], angles[3], angles[4])
        return ChainState(qf, origins, axes, r, jw, je, energy, grav)

    def _gravity(
        self, axes: list[Vec], origins: list[Vec], coms: list[Vec]
    ) -> tuple[float, list[float]]:
        """Potential energy [J] and its gradient [J/rad] from suffix sums over links.

        Joint k lifts every link beyond it: dE/dq_k = g * (a_k x (sum m c - M o_k))_z
        with M and sum m c taken over those links.
        """
        grav = [0.0] * 5
        mass = mx = my = mz = 0.0
        for k in range(4, -1, -1):
            m = self.links[k][0]
            cx, cy, cz = coms[k]
            mass, mx, my, mz = mass + m, mx + m * cx, my + m * cy, mz + m * cz
            ax, ay, _ = axes[k]
            ox, oy, _ = origins[k]
            grav[k] = self.gravity * (ax * (my - mass * oy) - ay * (mx - mass * ox))
        return self.gravity * mz, grav


def _columns(axes: list[Vec], origins: list[Vec], point: Vec, n: int) -> list[Vec]:
    """d(point)/dq_k = a_k x (point - o_k) for the first n joints."""
    out: list[Vec] = []
    wx, wy, wz = point
    for k in range(n):
        ax, ay, az = axes[k]
        ox, oy, oz = origins[k]
        dx, dy, dz = wx - ox, wy - oy, wz - oz
        out.append((ay * dz - az * dy, az * dx - ax * dz, ax * dy - ay * dx))
    return out


@cache
def _chain(side: Side) -> Chain:
    return Chain(load_arm(side))


def chain_for(arm: ArmModel) -> Chain:
    """The (cached) float chain of ``arm``'s side."""
    return _chain(arm.side)
