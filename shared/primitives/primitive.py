"""A movement primitive: its matrix, active joints, task and IK method."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum

from shared.primitives.matrix import PrimitiveMatrix, mp_form, mp_form_terms
from shared.robot.side import JOINTS


class PrimitiveType(StrEnum):
    """Motion primitives move the wrist; function primitives hold it (Table 1)."""

    MMP = "MMP"
    FMP = "FMP"


class Task(StrEnum):
    """What the primitive's IK controls at the wrist."""

    POSITION = "wrist position"
    POSE = "wrist position + orientation"
    HOLD = "wrist held, elbow swivels, wrist turns"
    TURN = "wrist turns in place"


class IKMethod(StrEnum):
    """How the primitive's inverse kinematics is solved (SPEC, primitive table)."""

    ELBOW_TRIANGLE = "geometric: arm triangle (eq. 11-12)"
    SHOULDER_ROTATION = "geometric: upper-arm rotation (eq. 13)"
    GPM_TPE = "GPM, H = TPE (eq. 14, 18)"
    GPM_GRASP = "GPM, H = H_G (eq. 14, 19-21)"
    GPM_NULL = "GPM null-space motion"
    WRIST_TURN = "analytic wrist turn"

    @property
    def geometric(self) -> bool:
        """True for the closed-form methods (no iteration)."""
        return self in (
            IKMethod.ELBOW_TRIANGLE,
            IKMethod.SHOULDER_ROTATION,
            IKMethod.WRIST_TURN,
        )


@dataclass(frozen=True)
class Primitive:
    """One movement primitive.

    Attributes:
        matrix: Primitive matrix e (equation 2), rows P, R, PR; columns S, E, W.
        kind: Motion (MMP) or function (FMP) primitive.
        active: Indices of the NAO joints it moves (0 ShoulderPitch ... 4 WristYaw).
        task: What its IK controls at the wrist.
        ik: How its IK is solved.
        name: a e j, computed from ``matrix`` (e.g. ``"S_R E_P W_P"``).
        terms: (node, attribute) pairs of a e j, e.g. (("S", "R"), ("E", "P")).
    """

    matrix: PrimitiveMatrix
    kind: PrimitiveType
    active: tuple[int, ...]
    task: Task
    ik: IKMethod
    name: str = field(init=False)
    terms: tuple[tuple[str, str], ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", mp_form(self.matrix))
        object.__setattr__(self, "terms", mp_form_terms(self.matrix))

    @property
    def active_joints(self) -> tuple[str, ...]:
        """Names of the active joints without side prefix, e.g. ``("ElbowRoll",)``."""
        return tuple(JOINTS[i] for i in self.active)

    @property
    def orients_wrist(self) -> bool:
        """True if the wrist's orientation changes actively (W_R or W_PR)."""
        return ("W", "R") in self.terms or ("W", "PR") in self.terms

    @property
    def moves_wrist(self) -> bool:
        """True if the wrist's position changes (W_P or W_PR)."""
        return ("W", "P") in self.terms or ("W", "PR") in self.terms

    def __str__(self) -> str:
        return self.name
